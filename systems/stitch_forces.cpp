#include "systems/stitch_forces.h"

#include <algorithm>

namespace clothsim {

void eval_stitches(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Real t, std::span<Vec3> f) {
  for (Index s = 0; s < m.stitch_count; ++s) {
    const Vec3 force = stitch_force(m, s, x, v, t);
    const auto c = stitch_coefficients(m.stitch_w[s]);
    const auto p = stitch_particles(m, s);
    for (int k = 0; k < 3; ++k) f[p[k]] += c[k] * force;
  }
}

Real stitch_excess(const Model& m, std::span<const Vec3> x, Real t) {
  Real worst = 0;
  for (Index s = 0; s < m.stitch_count; ++s)
    worst = std::max(worst, (stitch_combine(m, s, x) - stitch_target(m, s, t)).norm());
  return worst;
}

int apply_stitch_limit(const Model& m, State& out, Real h, Real t) {
  int it = 0;
  while (it < stitch_max_iterations && stitch_excess(m, out.x, t) > stitch_tolerance) {
    ++it;
    for (Index s = 0; s < m.stitch_count; ++s) {
      const Vec3 e = stitch_combine(m, s, out.x) - stitch_target(m, s, t);
      const Real len = e.norm();
      if (!(len > stitch_tolerance)) continue;
      const auto c = stitch_coefficients(m.stitch_w[s]);
      const auto p = stitch_particles(m, s);
      Real denom = 0;
      for (int k = 0; k < 3; ++k) denom += m.particle_inv_mass[p[k]] * c[k] * c[k];
      if (!(denom > 0)) continue;
      // Removing delta from the gap moves particle k by -inv_mass_k c_k delta / denom.
      const Vec3 delta = (1 - 0.5 * stitch_tolerance / len) * e;
      for (int k = 0; k < 3; ++k) {
        const Vec3 dx = (-m.particle_inv_mass[p[k]] * c[k] / denom) * delta;
        out.x[p[k]] += dx;
        out.v[p[k]] += dx / h;
      }
    }
  }
  return it;
}

}  // namespace clothsim
