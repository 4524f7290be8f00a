#include "systems/auto_step.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "systems/bend_forces.h"

namespace clothsim {

namespace {
constexpr Real implicit_accuracy_step = 0.02;  // s, backward Euler's step before step_safety
}  // namespace

Real auto_step_target(const SimOptions& o, const StableSteps& limits) {
  if (o.integrator == Integrator::implicit) return o.step_safety * implicit_accuracy_step;
  return o.step_safety * stable_step_limit(limits, o.integrator);
}

Real hinge_step_limit(const Model& m, std::span<const Vec3> x_rest) {
  const Real omega = m.hinge_count > 0 ? estimate_hinge_omega(m, x_rest) : 0;
  return omega > 0 ? 2 / (2 * omega) : std::numeric_limits<Real>::infinity();
}

StableSteps model_stable_steps(const Model& m, std::span<const Vec3> x_rest) {
  StableSteps limits = stable_steps(estimate_modes(m, x_rest));
  limits.hinges = hinge_step_limit(m, x_rest);
  return limits;
}

void choose_auto_step(const Model& m, SimOptions& o, std::span<const Vec3> x_rest, const std::string& scene_path) {
  const StableSteps limits = o.integrator == Integrator::implicit ? StableSteps{} : model_stable_steps(m, x_rest);
  const Real target = auto_step_target(o, limits);
  if (!(target > 0))
    throw Error(scene_path, "timestep=\"auto\": explicit Euler has no stable step for these springs (a stiff mode "
                            "has no damping); expected integrator=\"symplectic\", \"rk4\" or \"implicit\"");
  // The step count per frame comes from the same rounding as a written timestep (core/scene_desc.h).
  SimulationDesc sim;
  sim.fps = o.fps;
  sim.timestep = std::min<Real>(target, 1 / o.fps);
  o.steps_per_frame = steps_per_frame(sim);
  o.dt = 1.0 / (o.fps * o.steps_per_frame);
  // The rounding may land a hair above the target when it divides the frame to 1e-9: stay below it.
  if (o.dt > target) o.dt = 1.0 / (o.fps * ++o.steps_per_frame);
  if (!(o.min_dt > 0)) o.min_dt = o.dt / 1024;
}

}  // namespace clothsim
