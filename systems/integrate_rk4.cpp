#include "systems/integrate_rk4.h"

#include "systems/forces.h"

namespace clothsim {

// Each stage's update runs per particle as soon as its acceleration is known (eval_forces_then): inside the
// spring pass with the blocked layout, so the stage state is read and written while it is in cache.
StepCounts integrate_rk4(const Model& m, const State& in, State& out, Workspace& ws, Real h) {
  auto& xs = ws.stage_x;
  auto& vs = ws.stage_v;
  const auto& a = ws.f;
  auto& sum_x = out.x;  // sum of the k_x of the stages, weighted 1 2 2 (1 added at the end)
  auto& sum_v = out.v;

  StepCounts counts = eval_forces_then(m, in.x, in.v, in.time, ws, [&](Index i) {  // k1 = (v0, a(x0, v0))
    sum_x[i] = in.v[i];
    sum_v[i] = a[i];
    xs[i] = in.x[i] + 0.5 * h * in.v[i];
    vs[i] = in.v[i] + 0.5 * h * a[i];
  });
  // k2 and k3: each reads the previous stage, accumulates it twice, and prepares the next, in place (the stage
  // state of particle i is read by no spring after its update).
  for (const Real frac : {0.5, 1.0}) {
    counts.add(eval_forces_then(m, xs, vs, in.time, ws, [&](Index i) {
      const Vec3 v_stage = vs[i];
      sum_x[i] += 2.0 * v_stage;
      sum_v[i] += 2.0 * a[i];
      xs[i] = in.x[i] + frac * h * v_stage;
      vs[i] = in.v[i] + frac * h * a[i];
    }));
  }
  counts.add(eval_forces_then(m, xs, vs, in.time, ws, [&](Index i) {  // k4
    out.x[i] = in.x[i] + (h / 6.0) * (sum_x[i] + vs[i]);
    out.v[i] = in.v[i] + (h / 6.0) * (sum_v[i] + a[i]);
  }));
  return counts;
}

}  // namespace clothsim
