#include "systems/integrate_explicit.h"

#include "systems/forces.h"
#include "systems/parallel.h"

namespace clothsim {

void integrate_euler(std::span<const Vec3> x, std::span<const Vec3> v, std::span<const Vec3> a, Real h,
                     std::span<Vec3> x_out, std::span<Vec3> v_out) {
  parallel_over(Index(x.size()), particle_grain, [&](Index i) {
    const Vec3 vi = v[i];
    x_out[i] = x[i] + h * vi;
    v_out[i] = vi + h * a[i];
  });
}

StepCounts integrate_symplectic(const Model& m, const State& in, State& out, Workspace& ws, Real h) {
  const auto& a = ws.f;
  return eval_forces_then(m, in.x, in.v, in.time, ws, [&](Index i) {
    const Vec3 vn = in.v[i] + h * a[i];
    out.v[i] = vn;
    out.x[i] = in.x[i] + h * vn;
  });
}

}  // namespace clothsim
