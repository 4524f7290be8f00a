#include "systems/strain_limit.h"

#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <limits>

#include "systems/parallel.h"

namespace clothsim {
namespace {

// One Jacobi sweep's spring phase: stores the correction of each spring (added to a times inv_mass_a,
// subtracted from b times inv_mass_b) and returns the largest strain excess before the sweep.
Real propose_corrections(const Model& m, std::span<const Vec3> x, std::span<Vec3> correction) {
  return tbb::parallel_reduce(
      tbb::blocked_range<Index>(0, m.spring_count, 4 * particle_grain), -std::numeric_limits<Real>::infinity(),
      [&](const tbb::blocked_range<Index>& r, Real worst) {
        for (Index s = r.begin(); s != r.end(); ++s) {
          const Index a = m.spring_a[s], b = m.spring_b[s];
          const Vec3 d = x[b] - x[a];
          const Real len = d.norm(), rest = m.spring_rest[s], limit = m.spring_max_strain[s];
          const Real excess = (len - rest) / rest - limit;
          worst = std::max(worst, excess);
          const Real w = m.particle_inv_mass[a] + m.particle_inv_mass[b];
          correction[s] = excess > 0 && w > 0 ? Vec3((len - (1 + limit) * rest) / (w * len) * d) : Vec3::Zero();
        }
        return worst;
      },
      [](Real p, Real q) { return std::max(p, q); });
}

}  // namespace

int apply_strain_limit(const Model& m, State& out, Workspace& ws, Real h) {
  auto& corr = ws.strain_correction;
  int it = 0;
  for (; it < strain_limit_max_iterations; ++it) {
    // Stop a little inside the guarantee so the last sweep's round-off cannot cross it.
    if (propose_corrections(m, out.x, corr) <= 0.5 * strain_limit_tolerance) break;
    parallel_over(m.particle_count, particle_grain, [&](Index i) {
      const Real inv_m = m.particle_inv_mass[i];
      if (!(inv_m > 0)) return;
      Vec3 sum = Vec3::Zero();
      int active = 0;
      for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
        const Index e = m.particle_spring_index[k];
        const Vec3& c = corr[e >= 0 ? e : ~e];
        if (c.isZero(0)) continue;
        sum += e >= 0 ? c : Vec3(-c);
        ++active;
      }
      if (active == 0) return;
      const Vec3 dx = (inv_m / active) * sum;
      out.x[i] += dx;
      out.v[i] += dx / h;
    });
  }
  ws.strain_iterations_total += it;
  return it;
}

}  // namespace clothsim
