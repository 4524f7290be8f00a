#include "systems/stitch_forces.h"

#include <algorithm>
#include <cmath>

#include "systems/displace.h"
#include "systems/parallel.h"

namespace clothsim {

void set_stitch_rest(const Model& m, std::span<const Vec3> x0, std::span<const Vec3> v0, Real t_end, Real h,
                     std::span<Real> rest, std::span<Real> pull) {
  for (Index s = 0; s < m.stitch_count; ++s) {
    const Vec3 g = stitch_combine(m, s, x0);
    const Real l0 = g.norm();
    const Real closing = l0 > 0 ? std::max(Real(0), -g.dot(stitch_combine(m, s, v0)) / l0) : Real(0);
    const Real target = stitch_target_length(m, s, t_end);
    // Past its schedule (target 0) a gap still open is one the strain limit or a contact holds: it is pulled at
    // sewSpeed, with no ramp, so that it does not settle where the ramp's small steps balance the holding.
    const Real u = target > 0 ? std::min({stitch_speed(m, s), closing + stitch_acceleration * h,
                                          std::sqrt(2 * stitch_acceleration * l0)})
                              : stitch_speed(m, s);
    rest[s] = std::max(target, l0 - u * h);
    pull[s] = (l0 - rest[s]) / h;
  }
}

void eval_stitches(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<const Real> rest,
                   std::span<const Real> pull, std::span<Vec3> f) {
  for (Index s = 0; s < m.stitch_count; ++s) {
    const Vec3 force = stitch_terms(m, s, x, v, rest[s], pull[s]).force;
    const auto c = stitch_coefficients(m.stitch_w[s]);
    const auto p = stitch_particles(m, s);
    for (int k = 0; k < 3; ++k) f[p[k]] += c[k] * force;
  }
}

void build_stitch_blocks(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Real h, Workspace& ws) {
  parallel_over(m.stitch_count, particle_grain, [&](Index s) {
    const StitchTerms terms = stitch_terms(m, s, x, v, ws.stitch_rest[s], ws.stitch_pull[s]);
    ws.stitch_kx[s] = Sym3::from(terms.jac.dfdx);
    ws.stitch_block[s] = Sym3::from(spring_system_block(terms.jac, h));
  });
}

int apply_stitch_limit(const Model& m, std::span<const Real> rest, State& out, Real h, Real t) {
  int it = 0;
  for (bool moved = true; moved && it < stitch_max_iterations;) {
    moved = false;
    for (Index s = 0; s < m.stitch_count; ++s) {
      const Vec3 g = stitch_combine(m, s, out.x);
      const Real l = g.norm(), target = stitch_target_length(m, s, t), r = rest[s];
      // A clamped rest is exact, so the pass's tolerance cannot add to a held gap's lag step after step.
      Real aim;
      if (r > target) aim = l > r + stitch_clamped_tolerance ? r : -1;
      else aim = l > target + stitch_tolerance ? target + 0.5 * stitch_tolerance : -1;
      if (aim < 0) continue;
      const auto c = stitch_coefficients(m.stitch_w[s]);
      const auto p = stitch_particles(m, s);
      Real denom = 0;
      for (int k = 0; k < 3; ++k) denom += m.particle_inv_mass[p[k]] * c[k] * c[k];
      if (!(denom > 0) || !(l > 0)) continue;
      // Changing the gap by -delta (along itself, to the aimed length) moves particle k by
      // -inv_mass_k c_k delta / denom.
      moved = true;
      const Vec3 delta = (1 - aim / l) * g;
      for (int k = 0; k < 3; ++k) {
        displace(out, p[k], (-m.particle_inv_mass[p[k]] * c[k] / denom) * delta, h);
      }
    }
    if (moved) ++it;
  }
  return it;
}

}  // namespace clothsim
