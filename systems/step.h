#pragma once
// One time step, built from named stages in the style of MuJoCo's mj_step:
//   integrate (forces, then explicit Euler | symplectic Euler | RK4 | backward Euler) -> attachments ->
//   (stitch limit <-> strain limit, alternating) -> collide -> (stitch limit <-> strain limit with the collider
//   contacts held on their planes; implicit with the contact filter only).
// The steps of a frame, and the checks between them, are sim/frame_stepper.h's.
#include "core/model.h"
#include "systems/step_result.h"

namespace clothsim {

// Advances in by h into out (distinct states; out is resized by the caller once). The integrator is the
// options', chosen by one switch per step, never per particle. The result says whether the step failed (only the
// implicit solve can today) and what it did (systems/step_result.h).
StepResult step(const Model& model, const SimOptions& options, const State& in, State& out, Workspace& ws, Real h);

}  // namespace clothsim
