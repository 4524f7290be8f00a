#pragma once
#include "core/model.h"
#include "systems/step_result.h"

namespace clothsim {

// Classical fourth-order Runge-Kutta on (x, v): four force evaluations of the whole system per step. The
// running sums of the stage derivatives live in out.x / out.v, the stage state in ws.stage_x / ws.stage_v.
// Returns its four force stages' counts, summed (eval_forces).
StepCounts integrate_rk4(const Model& model, const State& in, State& out, Workspace& ws, Real h);

}  // namespace clothsim
