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

namespace {

// Springs [begin, end) of one block (at most spring_lane_block) into out. The endpoints are gathered into
// structure-of-arrays lanes first, so the arithmetic (sqrt and division bound, docs/performance.md) runs as one
// loop the compiler vectorises. It is spring_force_lane, the expression spring_force uses, so the two layouts
// stay bitwise equal (tests/spring_layouts_test.cpp).
// Uniform: ke and kd are one value each (stride-0 fields, an unmapped scene) and stay in registers; copying
// them into two more lanes per spring cost 27-29 % (docs/performance.md). The choice is made once per block.
constexpr Index spring_lane_block = 64;

template <bool Uniform>
void eval_spring_block(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Index begin, Index end,
                       Vec3* out) {
  alignas(64) Real dx[spring_lane_block], dy[spring_lane_block], dz[spring_lane_block];
  alignas(64) Real dvx[spring_lane_block], dvy[spring_lane_block], dvz[spring_lane_block];
  alignas(64) Real rest[spring_lane_block], ke[spring_lane_block], kd[spring_lane_block];
  alignas(64) Real fx[spring_lane_block], fy[spring_lane_block], fz[spring_lane_block];
  const Index n = end - begin;
  for (Index k = 0; k < n; ++k) {
    const Index s = begin + k, a = m.spring_a[s], b = m.spring_b[s];
    dx[k] = x[b][0] - x[a][0]; dy[k] = x[b][1] - x[a][1]; dz[k] = x[b][2] - x[a][2];
    dvx[k] = v[b][0] - v[a][0]; dvy[k] = v[b][1] - v[a][1]; dvz[k] = v[b][2] - v[a][2];
    rest[k] = m.spring_rest[s];
    if constexpr (!Uniform) { ke[k] = m.spring_ke[s]; kd[k] = m.spring_kd[s]; }
  }
  const Real ke0 = m.spring_ke[0], kd0 = m.spring_kd[0];
  for (Index k = 0; k < n; ++k) {
    const SpringLane f = spring_force_lane(dx[k], dy[k], dz[k], dvx[k], dvy[k], dvz[k], rest[k],
                                           Uniform ? ke0 : ke[k], Uniform ? kd0 : kd[k]);
    fx[k] = f.fx;
    fy[k] = f.fy;
    fz[k] = f.fz;
  }
  for (Index k = 0; k < n; ++k) out[k] = Vec3(fx[k], fy[k], fz[k]);
}

void eval_spring_block(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Index begin, Index end,
                       Vec3* out) {
  if (m.spring_ke.uniform() && m.spring_kd.uniform()) eval_spring_block<true>(m, x, v, begin, end, out);
  else eval_spring_block<false>(m, x, v, begin, end, out);
}

}  // namespace

void eval_springs_two_phase(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f,
                            std::span<Vec3> spring_force_out) {
  const Index blocks = (m.spring_count + spring_lane_block - 1) / spring_lane_block;
  parallel_over(blocks, 4 * particle_grain / spring_lane_block, [&](Index blk) {
    const Index begin = blk * spring_lane_block;
    eval_spring_block(m, x, v, begin, std::min(begin + spring_lane_block, m.spring_count),
                      spring_force_out.data() + begin);
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

void eval_springs_blocked(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) { f[i] = Vec3::Zero(); });
  const Index passes = Index(m.spring_pass_offset.size()) - 1;
  for (Index p = 0; p < passes; ++p) {
    const Index first = m.spring_pass_offset[p];
    // One chunk per task: chunks of a pass touch disjoint particles, and a chunk adds in spring order.
    parallel_over(m.spring_pass_offset[p + 1] - first, 1, [&](Index k) {
      const Index chunk = m.spring_pass_chunk[first + k];
      const Index end = m.spring_chunk_offset[chunk + 1];
      Vec3 lane[spring_lane_block];
      for (Index begin = m.spring_chunk_offset[chunk]; begin < end; begin += spring_lane_block) {
        const Index stop = std::min(begin + spring_lane_block, end);
        eval_spring_block(m, x, v, begin, stop, lane);
        for (Index s = begin; s < stop; ++s) {
          f[m.spring_a[s]] += lane[s - begin];
          f[m.spring_b[s]] -= lane[s - begin];
        }
      }
    });
  }
}

void eval_springs(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f,
                  std::span<Vec3> spring_scratch) {
  if (m.spring_layout == SpringLayout::blocked) eval_springs_blocked(m, x, v, f);
  else if (m.spring_layout == SpringLayout::two_phase) eval_springs_two_phase(m, x, v, f, spring_scratch);
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
