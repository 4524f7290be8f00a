#pragma once
// One time step, built from named stages in the style of MuJoCo's mj_step:
//   eval_forces -> integrate (explicit Euler | symplectic Euler | RK4 | backward Euler) -> strain limit -> collide
#include "core/model.h"
#include "systems/step_result.h"

namespace clothsim {

// Advances in by h into out (distinct states; out is resized by the caller once). The integrator is the
// model's, chosen by one switch per step, never per particle. The result says whether the step failed (only the
// implicit solve can today).
StepResult step(const Model& model, const State& in, State& out, Workspace& ws, Real h);

// Advances one frame (model.steps_per_frame steps of model.dt), swapping between state and scratch.
void step_frame(const Model& model, State& state, State& scratch, Workspace& ws);

}  // namespace clothsim
