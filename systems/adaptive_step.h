#pragma once
// timestep="auto": the step chosen from the stability estimate, and a frame loop that rejects a bad step and
// retries it at half the size, growing back when steps are easy (docs/stability.md, "Automatic steps").
#include <span>
#include <string>
#include <vector>

#include "core/model.h"
#include "systems/stability.h"

namespace clothsim {

// The step auto aims for before dividing the frame: step_safety x the integrator's stable step for explicit
// integrators; for backward Euler, which has no stability limit, step_safety x 20 ms (accuracy: its numerical
// damping of a mode of frequency w over a step is 1/(1 + (h w)^2)), the solver's health then halving it.
// 0 when there is none (explicit Euler on an undamped stiff mode).
Real auto_step_target(const Model& model, const StableSteps& limits);

// Sets model.dt and model.steps_per_frame for timestep="auto": the largest step that divides a frame evenly and
// does not exceed auto_step_target; min_dt defaults to dt / 1024. Throws Error naming the scene when explicit
// Euler has no stable step.
void choose_auto_step(Model& model, std::span<const Vec3> x_rest, const std::string& scene_path);

// Steps of one frame, for --stats.
struct FrameSteps {
  int taken = 0, rejected = 0;
  Real smallest = 0, largest = 0;  // s, accepted steps
};

// Why a step was rejected; `none` for an accepted one.
enum class StepVerdict { none, failed_solve, non_finite, strain_jump, energy_jump };
const char* verdict_name(StepVerdict verdict);

// A step is rejected when its result failed, is not finite, raises the largest spring strain by more than
// strain_jump in one step, or takes the mechanical energy past its start by more than the run's bound
// (energy_rise_bound, systems/stability.h). Rejection keeps the state the step started from (step writes into
// scratch only), halves the step and retries; after grow_after accepted steps in a row the step doubles again,
// up to model.dt, when that keeps the frame's steps aligned. Each frame starts again at model.dt. Every decision uses deterministic sums, so the
// steps are the same at any thread count.
class AdaptiveStepper {
 public:
  static constexpr Real strain_jump = 0.1;
  static constexpr int grow_after = 16;

  // start: the scene's initial state (energies are measured from it, as the run's divergence guard does).
  AdaptiveStepper(const Model& model, const State& start);
  // Advances state by one frame; false when a step below model.min_dt was rejected (the run diverged): state is
  // then the last accepted one, inside the frame.
  bool advance_frame(const Model& model, State& state, State& scratch, Workspace& ws, FrameSteps& report);
  StepVerdict last_rejection() const { return last_; }
  Real current_step(const Model& model) const;

 private:
  std::vector<Vec3> x_start_;
  Real energy_start_ = 0, energy_bound_ = 0;
  int level_ = 0;  // step = model.dt / 2^level
  int easy_ = 0;   // accepted steps in a row at this level
  StepVerdict last_ = StepVerdict::none;
};

}  // namespace clothsim
