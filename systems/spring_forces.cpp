#include "systems/spring_forces.h"

#include <tbb/parallel_reduce.h>

#include <algorithm>

#include "systems/parallel.h"

namespace clothsim {

void eval_springs_gather(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    Vec3 sum = Vec3::Zero();
    for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
      const Index e = m.particle_spring_index[k];
      const Index s = e >= 0 ? e : ~e;
      const Vec3 fa = spring_force(x[m.spring_a[s]], x[m.spring_b[s]], v[m.spring_a[s]], v[m.spring_b[s]],
                                   m.spring_rest[s], m.spring_ke[s], m.spring_kd[s]);
      sum += e >= 0 ? fa : Vec3(-fa);
    }
    f[i] = sum;
  });
}

void eval_springs_two_phase(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f,
                            std::span<Vec3> spring_force_out) {
  parallel_over(m.spring_count, 4 * particle_grain, [&](Index s) {
    const Index a = m.spring_a[s], b = m.spring_b[s];
    spring_force_out[s] = spring_force(x[a], x[b], v[a], v[b], m.spring_rest[s], m.spring_ke[s], m.spring_kd[s]);
  });
  gather_spring_forces(m, spring_force_out, f);
}

void gather_spring_forces(const Model& m, std::span<const Vec3> spring_force, std::span<Vec3> f) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    Vec3 sum = Vec3::Zero();
    for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
      const Index e = m.particle_spring_index[k];
      if (e >= 0) sum += spring_force[e];
      else sum -= spring_force[~e];
    }
    f[i] = sum;
  });
}

void eval_springs(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f,
                  std::span<Vec3> spring_scratch) {
  if (m.spring_layout == SpringLayout::two_phase) eval_springs_two_phase(m, x, v, f, spring_scratch);
  else eval_springs_gather(m, x, v, f);
}

Real max_spring_strain(const Model& m, std::span<const Vec3> x) {
  return tbb::parallel_reduce(
      tbb::blocked_range<Index>(0, m.spring_count, 4 * particle_grain), Real(0),
      [&](const tbb::blocked_range<Index>& r, Real best) {
        for (Index s = r.begin(); s != r.end(); ++s) {
          const Real len = (x[m.spring_b[s]] - x[m.spring_a[s]]).norm();
          best = std::max(best, (len - m.spring_rest[s]) / m.spring_rest[s]);
        }
        return best;
      },
      [](Real a, Real b) { return std::max(a, b); });
}

}  // namespace clothsim
