#include "systems/auto_step.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace clothsim {

namespace {
constexpr Real implicit_accuracy_step = 0.02;  // s, backward Euler's step before step_safety
}  // namespace

Real auto_step_target(const Model& m, const StableSteps& limits) {
  if (m.integrator == Integrator::implicit) return m.step_safety * implicit_accuracy_step;
  return m.step_safety * stable_step_limit(limits, m.integrator);
}

void choose_auto_step(Model& m, std::span<const Vec3> x_rest, const std::string& scene_path) {
  const StableSteps limits = m.integrator == Integrator::implicit ? StableSteps{}
                                                                   : stable_steps(estimate_modes(m, x_rest));
  const Real target = auto_step_target(m, limits);
  if (!(target > 0))
    throw Error(scene_path, "timestep=\"auto\": explicit Euler has no stable step for these springs (a stiff mode "
                            "has no damping); expected integrator=\"symplectic\", \"rk4\" or \"implicit\"");
  // The step count per frame comes from the same rounding as a written timestep (core/scene_desc.h).
  SimulationDesc sim;
  sim.fps = m.fps;
  sim.timestep = std::min<Real>(target, 1 / m.fps);
  m.steps_per_frame = steps_per_frame(sim);
  m.dt = 1.0 / (m.fps * m.steps_per_frame);
  // The rounding may land a hair above the target when it divides the frame to 1e-9: stay below it.
  if (m.dt > target) m.dt = 1.0 / (m.fps * ++m.steps_per_frame);
  if (!(m.min_dt > 0)) m.min_dt = m.dt / 1024;
}

}  // namespace clothsim
