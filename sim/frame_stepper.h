#pragma once
// The steps of one frame (docs/stability.md, "Automatic steps"). With a fixed timestep: steps_per_frame steps of
// dt; each implicit step is checked and one that fails its check is kept and reported. With timestep="auto": a
// step that fails its check is rejected and retried at half the size, growing back when steps are easy.
#include <span>
#include <vector>

#include "core/model.h"
#include "systems/step_result.h"

namespace clothsim::sim {

// Why a step failed its check; `none` for a sound one.
enum class StepVerdict { none, failed_solve, non_finite, strain_jump, energy_jump, strain_limit, zones_unresolved };
const char* verdict_name(StepVerdict verdict);
// True when a strain jump past strain_before + strain_jump is the collide stage's alone and either no collider-mesh
// vertex or cloth particle moved by more than travel_fraction of the thickness in the step, or the step is the
// smallest allowed (at_floor) (a timestep="auto" step).
bool collide_stage_jump(const Model& model, const StepResult& result, Real strain_before, bool at_floor);
// A step's own failure (the strain limit's, then the solve's) before the frame loop's checks, or a strain jump.
StepVerdict failure_verdict(const StepResult& result, bool strain_jumped);

// A step that failed its check and was kept (fixed timestep), as `run` reports it.
struct StepFailure {
  StepVerdict verdict = StepVerdict::none;
  Real step = 0;                             // s
  Real strain_before = 0, strain_after = 0;  // largest spring strain (|d| - rest)/rest at the step's ends
  SolveRecord solve;                         // the implicit solve's record
};

// Steps of one frame, for --stats and the run's warning.
struct FrameSteps {
  int taken = 0, rejected = 0;
  Real smallest = 0, largest = 0;  // s, accepted steps
  int failed = 0;                  // accepted steps that failed their check and were kept
  StepFailure first_failure;       // the first of them
  StepVerdict last_rejection = StepVerdict::none;  // why the frame's last rejected step was rejected
  std::vector<SolveRecord> solves; // implicit: every solve of the frame, rejected steps' included, in order
  StepCounts counts;               // what every step of the frame did, rejected ones included
};

// The checks: a step fails when its result failed (the implicit solve stopped at cgMaxIterations or a Newton
// correction raised the residual), is not finite, raises the largest spring strain by more than strain_jump in
// one step, takes the mechanical energy past its start by more than the run's bound (energy_rise_bound,
// systems/stability.h), or (timestep="auto", above the floor step) ends with impact zones unresolved while a
// collider-mesh vertex moved by more than travel_fraction of the thickness. With a fixed timestep only the
// implicit integrator's steps are checked, on the solve and the strain; the frame's end is checked by the run's
// divergence guard (sim/simulation.h).
//
// A rejection keeps the state the step started from (step writes into scratch only), halves the step and
// retries; a strain jump that the collide stage made while neither collider nor cloth moved by a quarter of the
// thickness, or at minTimestep (collide_stage_jump), is kept and counted in `failed`; one that a probe at the
// floor step repeats is kept as the probe's step (jump_stays_at_floor); after either the step grows back at
// every aligned point until a step is rejected. Otherwise, after grow_after accepted steps in a row the step doubles again, up to options.dt, when that keeps the
// frame's steps aligned. Each frame starts again at options.dt, so a frame's steps depend on its start state
// alone and a run resumed from a checkpoint takes the same steps. Every decision uses deterministic sums: the
// steps are the same at any thread count.
class FrameStepper {
 public:
  // More than this rise of the largest spring strain within one step is far beyond what a converged step of cloth
  // does: the linearisation about the step's start was taken too far.
  static constexpr Real strain_jump = 0.1;
  // A strain jump is the collide stage's alone when the strain before that stage rose by no more than
  // strain_jump; it is kept when no collider-mesh vertex and no cloth particle moved by more than this fraction
  // of the thickness in the step: a smaller step then would not push much less (docs/stability.md, "Automatic
  // steps").
  static constexpr Real travel_fraction = 0.25;
  // Otherwise the step is tried once more from the same start at the floor step (the smallest dt / 2^k not below
  // minTimestep: a probe): when that step still makes at least this fraction of the jump in its collide stage,
  // the jump does not come from motion over the step, and the probe's step is kept and reported: the state ten
  // halvings would have reached, for the cost of one step.
  static constexpr Real floor_keep_ratio = 0.5;
  static constexpr int grow_after = 16;

  // start: the scene's initial state (energies are measured from it, as the run's divergence guard does).
  FrameStepper(const Model& model, const SimOptions& options, const State& start);
  // Advances state by one frame; false when a step below options.min_dt was rejected (timestep="auto" only): state
  // is then the last accepted one, inside the frame.
  bool advance_frame(const Model& model, const SimOptions& options, State& state, State& scratch, Workspace& ws,
                     FrameSteps& report);
  // The step the stepper takes now: options.dt with a fixed timestep.
  Real current_step(const SimOptions& options) const;

  // The divergence guard's terms: the mechanical energy's rise since the start, J, and its bound.
  Real energy_rise(const Model& model, const State& state) const;
  Real energy_bound() const { return energy_bound_; }
  std::span<const Vec3> start_positions() const { return x_start_; }

 private:
  void fixed_frame(const Model& model, const SimOptions& options, State& state, State& scratch, Workspace& ws,
                   FrameSteps& report);
  // The probe of floor_keep_ratio: whether a collide-stage jump of `jump` from `start` (largest strain `strain`)
  // is still made, by that fraction at least, by a step at the floor level; then probe_ holds that step's end and
  // probe_strain its largest strain. Counts one rejected step: the probe, or the whole step it replaces.
  bool jump_stays_at_floor(const Model& model, const SimOptions& options, const State& start, Workspace& ws,
                           const StepResult& result, Real strain, Real jump, FrameSteps& report, Real& probe_strain);
  // The level of the smallest step dt / 2^level that is not below options.min_dt (at most 40 halvings): a step
  // there is the smallest allowed.
  static int floor_level(const SimOptions& options);
  State probe_;               // the probe step's end; allocated at the first probe
  StepResult probe_result_;   // and what it did
  std::vector<Vec3> x_start_;
  Real energy_start_ = 0, energy_bound_ = 0;
  int level_ = 0;  // step = options.dt / 2^level
  int easy_ = 0;   // accepted steps in a row at this level
  int floor_level_ = 0;  // floor_level(options) of the frame
  bool fast_grow_ = false;  // since the last rejection, a jump was kept: grow at every aligned point
};

}  // namespace clothsim::sim
