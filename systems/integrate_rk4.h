#pragma once
#include "core/model.h"

namespace clothsim {

// Classical fourth-order Runge-Kutta on (x, v): four force evaluations of the whole system per step. The
// running sums of the stage derivatives live in out.x / out.v, the stage state in ws.stage_x / ws.stage_v.
// Returns the wall time of its four force stages, s.
double integrate_rk4(const Model& model, const State& in, State& out, Workspace& ws, Real h);

}  // namespace clothsim
