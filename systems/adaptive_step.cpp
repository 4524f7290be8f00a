#include "systems/adaptive_step.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "core/error.h"
#include "systems/diagnostics.h"
#include "systems/spring_forces.h"
#include "systems/step.h"

namespace clothsim {

namespace {
constexpr Real implicit_accuracy_step = 0.02;  // s, backward Euler's step before step_safety
constexpr int max_level = 40;                  // halvings; min_dt stops far earlier
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

const char* verdict_name(StepVerdict v) {
  switch (v) {
    case StepVerdict::none: return "accepted";
    case StepVerdict::failed_solve: return "its linear solve stopped at cgMaxIterations";
    case StepVerdict::non_finite: return "non-finite positions or velocities";
    case StepVerdict::strain_jump: return "the largest strain jumped by more than 0.1 in one step";
    case StepVerdict::energy_jump: return "the mechanical energy rose past its bound";
  }
  return "";
}

AdaptiveStepper::AdaptiveStepper(const Model& m, const State& start) : x_start_(start.x) {
  energy_start_ = mechanical_energy(m, start, x_start_);
  energy_bound_ = energy_rise_bound(m, x_start_);
}

Real AdaptiveStepper::current_step(const Model& m) const { return std::ldexp(m.dt, -level_); }

bool AdaptiveStepper::advance_frame(const Model& m, State& state, State& scratch, Workspace& ws,
                                    FrameSteps& report) {
  report = {};
  // Every frame starts at the chosen step: a frame's steps depend on its start state alone, so a run resumed
  // from a checkpoint takes the same steps as the whole run.
  level_ = 0;
  easy_ = 0;
  Real strain = max_spring_strain(m, state.x);
  // Position inside the frame in steps of the current level; the frame ends at steps_per_frame << level.
  std::int64_t pos = 0;
  while (pos < (std::int64_t(m.steps_per_frame) << level_)) {
    const Real h = current_step(m);
    const StepResult result = step(m, state, scratch, ws, h);
    StepVerdict verdict = StepVerdict::none;
    Real strain_after = strain;
    if (result.failed) verdict = StepVerdict::failed_solve;
    else if (!state_is_finite(scratch)) verdict = StepVerdict::non_finite;
    else if ((strain_after = max_spring_strain(m, scratch.x)) > strain + strain_jump) verdict = StepVerdict::strain_jump;
    else if (!(mechanical_energy(m, scratch, x_start_) - energy_start_ <= energy_bound_))
      verdict = StepVerdict::energy_jump;
    if (verdict != StepVerdict::none) {
      // Rejected: state still holds the step's start, untouched (step wrote into scratch only).
      ++report.rejected;
      last_ = verdict;
      if (0.5 * h < m.min_dt || level_ >= max_level) return false;
      ++level_;
      pos *= 2;
      easy_ = 0;
      continue;
    }
    std::swap(state, scratch);
    strain = strain_after;
    ++pos;
    ++report.taken;
    report.smallest = report.taken == 1 ? h : std::min(report.smallest, h);
    report.largest = std::max(report.largest, h);
    // Grow back after a run of easy steps, when the doubled step still ends on the frame.
    if (++easy_ >= grow_after && level_ > 0 && pos % 2 == 0) {
      --level_;
      pos /= 2;
      easy_ = 0;
    }
  }
  return true;
}

}  // namespace clothsim
