#include "systems/bend_forces.h"

#include <algorithm>
#include <cmath>

#include "systems/parallel.h"
#include "systems/reduce.h"

namespace clothsim {

void eval_hinges(const Model& m, std::span<const Vec3> x, std::span<Vec3> hinge_force, std::span<Vec3> f) {
  parallel_over(m.hinge_count, particle_grain, [&](Index h) {
    const auto fh = hinge_forces(x[m.hinge_o1[h]], x[m.hinge_o2[h]], x[m.hinge_e0[h]], x[m.hinge_e1[h]],
                                 m.hinge_rest_angle[h], m.hinge_k[h]);
    for (int k = 0; k < 4; ++k) hinge_force[4 * std::size_t(h) + k] = fh[k];
  });
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    for (Index k = m.particle_hinge_offset[i]; k < m.particle_hinge_offset[i + 1]; ++k)
      f[i] += hinge_force[m.particle_hinge_index[k]];
  });
}

void build_hinge_jacobians(const Model& m, std::span<const Vec3> x, std::span<Vec3> u) {
  parallel_over(m.hinge_count, particle_grain, [&](Index h) {
    const Vec3 &o1 = x[m.hinge_o1[h]], &o2 = x[m.hinge_o2[h]], &e0 = x[m.hinge_e0[h]], &e1 = x[m.hinge_e1[h]];
    const HingeFrame fr = hinge_frame(o1, o2, e0, e1);
    const std::size_t b = 4 * std::size_t(h);
    if (!hinge_live(fr)) {
      for (int k = 0; k < 4; ++k) u[b + k] = Vec3::Zero();
      return;
    }
    const auto g = hinge_angle_gradient(o1, o2, e0, e1, fr);
    const Real scale = std::sqrt(2 * m.hinge_k[h]);
    for (int k = 0; k < 4; ++k) u[b + k] = scale * g[k];
  });
}

Real hinge_potential_energy(const Model& m, std::span<const Vec3> x) {
  return deterministic_sum(m.hinge_count, particle_grain, Real(0), [&](Index h) {
    return hinge_energy(x[m.hinge_o1[h]], x[m.hinge_o2[h]], x[m.hinge_e0[h]], x[m.hinge_e1[h]],
                        m.hinge_rest_angle[h], m.hinge_k[h]);
  });
}

Real estimate_hinge_omega(const Model& m, std::span<const Vec3> x) {
  Real largest = 0;
  for (Index h = 0; h < m.hinge_count; ++h) {
    const std::array<Index, 4> p = hinge_particles(m, h);
    const HingeFrame fr = hinge_frame(x[p[0]], x[p[1]], x[p[2]], x[p[3]]);
    if (!hinge_live(fr)) continue;
    const auto g = hinge_angle_gradient(x[p[0]], x[p[1]], x[p[2]], x[p[3]], fr);
    Real gmg = 0;
    for (int k = 0; k < 4; ++k) gmg += m.particle_inv_mass[p[k]] * g[k].squaredNorm();
    largest = std::max(largest, 2 * m.hinge_k[h] * gmg);
  }
  return std::sqrt(largest);
}

}  // namespace clothsim
