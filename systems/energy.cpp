#include "systems/energy.h"

#include <tbb/parallel_reduce.h>

#include "systems/parallel.h"

namespace clothsim {

Real spring_potential_energy(const Model& m, std::span<const Vec3> x) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<Index>(0, m.spring_count, 4 * particle_grain), Real(0),
      [&](const tbb::blocked_range<Index>& r, Real sum) {
        for (Index s = r.begin(); s != r.end(); ++s) {
          const Real stretch = (x[m.spring_b[s]] - x[m.spring_a[s]]).norm() - m.spring_rest[s];
          sum += 0.5 * m.spring_ke[s] * stretch * stretch;
        }
        return sum;
      },
      [](Real a, Real b) { return a + b; });
}

}  // namespace clothsim
