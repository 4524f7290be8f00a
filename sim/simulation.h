#pragma once
// The one frame loop every front end shares (DESIGN.md, "The way data flows"): a scene's Model, State and
// Workspace, advanced a frame at a time with the scene's step control (sim/frame_stepper.h) and the divergence
// guard of docs/stability.md, reporting what `run --stats` writes. `clothsim run`, the studies, the benchmarks
// and the tests step frames through it.
#include <cstdint>
#include <string>
#include <vector>

#include "core/build_model.h"
#include "core/model.h"
#include "sim/collider_track.h"
#include "sim/frame_stepper.h"
#include "sim/load_scene.h"

namespace clothsim::sim {

// Frames that ended past their cloth's maxStrain, and the worst of them.
struct LimitOverrun {
  std::int64_t stepped = 0;  // frames computed by steps (after the start frame)
  std::int64_t frames = 0;   // of them, those past the limit
  int worst_frame = 0;
  Real worst_excess = 0;  // (|d| - rest)/rest - maxStrain of its worst spring
  Real worst_strain = 0;  // that frame's largest strain over all springs
};

struct FrameReport {
  int frame = 0;            // the frame the state is now at
  FrameSteps steps;         // steps taken and rejected, failed checks, solves and what the steps did
  bool diverged = false;    // the state is not to be written: see `divergence`
  std::string divergence;   // why, with the step that failed and the remedy, in words; empty unless diverged
  Real max_strain = 0;      // largest (|d| - rest)/rest over all springs at the frame's end
  // Largest (|d| - rest)/rest - maxStrain over the limited springs at the frame's end; 0 without maxStrain.
  Real strain_excess = 0;
  Real kinetic_energy = 0;  // J
};

class Simulation {
 public:
  // The scene's initial state is the divergence guard's reference (its energy and rest positions). A scene with
  // animated colliders needs its track (made from its SceneDesc) to stream their frames.
  explicit Simulation(BuiltScene built, ColliderTrack track = {});
  // A loaded scene, copied: its model, initial state and collider track.
  explicit Simulation(const LoadedScene& scene) : Simulation(scene.built, ColliderTrack(scene.desc)) {}

  const Model& model() const { return model_; }
  const SimOptions& options() const { return options_; }
  const State& state() const { return state_; }
  Workspace& workspace() { return ws_; }
  const Workspace& workspace() const { return ws_; }
  // The frame advance_frame computes next: the scene's startFrame at first.
  int next_frame() const { return next_frame_; }
  // Steps that failed their check and were kept (fixed timestep), over the run, and the first of them.
  std::int64_t failed_steps() const { return failed_steps_; }
  const std::string& first_failure() const { return first_failure_; }
  // Computed frames (after the start) that ended with a limited spring past maxStrain + strain_limit_tolerance:
  // the strain limit after the collide stage leaves a spring that the contacts hold stretched (a pinch, a layer
  // held over a seam) for the step control, which rejects only jumps. `run` warns about them after the last frame.
  const LimitOverrun& limit_overrun() const { return overrun_; }
  // What every step of the run did, summed (force evaluations, CG iterations, contacts, stage times).
  const StepCounts& totals() const { return totals_; }

  // Continues from `state`, the state at `frame` (a checkpoint), with the Cholesky renewal run then: the next frame
  // computed is frame + 1. The guard keeps measuring from the scene's initial state, so a resumed run is judged
  // like a whole one.
  void resume(State state, int frame, const CholeskyRenewal& renewal);

  // Computes next_frame(): at the start frame the initial state itself, after it one frame of steps. When the
  // report says diverged, the state is the last one reached and nothing further should be asked of it.
  FrameReport advance_frame();

 private:
  Model model_;
  SimOptions options_;
  State state_, scratch_;
  Workspace ws_;
  ColliderTrack track_;
  FrameStepper stepper_;
  int next_frame_;
  Real last_strain_ = 0;  // largest spring strain of the last frame computed
  std::int64_t failed_steps_ = 0;
  StepCounts totals_;
  std::string first_failure_;
  LimitOverrun overrun_;
};

// The sentence `run` prints after the last frame when frames ended past maxStrain; empty when none did.
std::string describe_overrun(const LimitOverrun& overrun);

// The sentence `run` prints for a step that failed its check and was kept.
std::string describe_failure(const SimOptions& options, const StepFailure& failure, int frame);

}  // namespace clothsim::sim
