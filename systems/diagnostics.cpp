#include "systems/diagnostics.h"

#include <tbb/parallel_reduce.h>

#include <cmath>

#include "systems/parallel.h"

namespace clothsim {

Real kinetic_energy(const Model& m, std::span<const Vec3> v) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<Index>(0, m.particle_count, particle_grain), Real(0),
      [&](const tbb::blocked_range<Index>& r, Real sum) {
        for (Index i = r.begin(); i != r.end(); ++i) {
          const Real inv_m = m.particle_inv_mass[i];
          if (inv_m > 0) sum += 0.5 * v[i].squaredNorm() / inv_m;
        }
        return sum;
      },
      [](Real a, Real b) { return a + b; });
}

bool state_is_finite(const State& s) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, s.x.size(), particle_grain), true,
      [&](const tbb::blocked_range<std::size_t>& r, bool ok) {
        for (std::size_t i = r.begin(); ok && i != r.end(); ++i) ok = s.x[i].allFinite() && s.v[i].allFinite();
        return ok;
      },
      [](bool a, bool b) { return a && b; });
}

}  // namespace clothsim
