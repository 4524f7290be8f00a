#include "systems/spring_forces.h"

#include <tbb/parallel_reduce.h>

#include <algorithm>

#include "systems/parallel.h"

namespace clothsim {

void eval_springs_gather(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f) {
  with_forms(m.spring_ke, m.spring_kd, [&](auto ke, auto kd) {
    parallel_over(m.particle_count, particle_grain, [&](Index i) {
      Vec3 sum = Vec3::Zero();
      for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
        const Index e = m.particle_spring_index[k];
        const Index s = e >= 0 ? e : ~e;
        const Vec3 fa = spring_force(x[m.spring_a[s]], x[m.spring_b[s]], v[m.spring_a[s]], v[m.spring_b[s]],
                                     m.spring_rest[s], m.spring_ke.at<decltype(ke)::value>(s),
                                     m.spring_kd.at<decltype(kd)::value>(s));
        sum += e >= 0 ? fa : Vec3(-fa);
      }
      f[i] = sum;
    });
  });
}

namespace {

// Springs [begin, end) of one block (at most spring_lane_block) into structure-of-arrays lanes. The endpoints
// are gathered into lanes first, so the arithmetic (sqrt and division bound: docs/performance.md) runs as one
// loop the compiler vectorises. It is spring_force_lane, the expression spring_force uses, so the layouts stay
// bitwise equal (tests/unit/spring_layouts_test.cpp). Each of ke and kd is read in its field's form (chosen once per
// block, not per spring): a uniform value stays a scalar, broadcast into the vector loop; a palette is read
// through its one-byte codes from a table in L1; only a per-element field streams 8 bytes a spring.
constexpr Index spring_lane_block = spring_block_size;

using Form = ParamField::Form;

template <Form ke_form, Form kd_form>
void eval_spring_lanes(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Index begin, Index end,
                       SpringLanes& out) {
  alignas(64) Real dx[spring_lane_block], dy[spring_lane_block], dz[spring_lane_block];
  alignas(64) Real dvx[spring_lane_block], dvy[spring_lane_block], dvz[spring_lane_block];
  alignas(64) Real rest[spring_lane_block], ke[spring_lane_block], kd[spring_lane_block];
  const Index n = end - begin;
  for (Index k = 0; k < n; ++k) {
    const Index s = begin + k, a = m.spring_a[s], b = m.spring_b[s];
    dx[k] = x[b][0] - x[a][0]; dy[k] = x[b][1] - x[a][1]; dz[k] = x[b][2] - x[a][2];
    dvx[k] = v[b][0] - v[a][0]; dvy[k] = v[b][1] - v[a][1]; dvz[k] = v[b][2] - v[a][2];
    rest[k] = m.spring_rest[s];
    if constexpr (ke_form != Form::uniform) ke[k] = m.spring_ke.at<ke_form>(s);
    if constexpr (kd_form != Form::uniform) kd[k] = m.spring_kd.at<kd_form>(s);
  }
  const Real ke0 = m.spring_ke.data()[0], kd0 = m.spring_kd.data()[0];
  for (Index k = 0; k < n; ++k) {
    const SpringLane f = spring_force_lane(dx[k], dy[k], dz[k], dvx[k], dvy[k], dvz[k], rest[k],
                                           ke_form == Form::uniform ? ke0 : ke[k],
                                           kd_form == Form::uniform ? kd0 : kd[k]);
    out.fx[k] = f.fx;
    out.fy[k] = f.fy;
    out.fz[k] = f.fz;
  }
}

}  // namespace

void eval_spring_block(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Index begin, Index end,
                       SpringLanes& out) {
  with_forms(m.spring_ke, m.spring_kd, [&](auto ke, auto kd) {
    eval_spring_lanes<decltype(ke)::value, decltype(kd)::value>(m, x, v, begin, end, out);
  });
}

void eval_springs_two_phase(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f,
                            std::span<Vec3> spring_force_out) {
  const Index blocks = (m.spring_count + spring_lane_block - 1) / spring_lane_block;
  parallel_over(blocks, 4 * particle_grain / spring_lane_block, [&](Index blk) {
    const Index begin = blk * spring_lane_block;
    const Index end = std::min(begin + spring_lane_block, m.spring_count);
    SpringLanes lanes;
    eval_spring_block(m, x, v, begin, end, lanes);
    for (Index s = begin; s < end; ++s)
      spring_force_out[s] = Vec3(lanes.fx[s - begin], lanes.fy[s - begin], lanes.fz[s - begin]);
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
  eval_springs_blocked_then(m, x, v, f, [](Index) {});
}

void eval_springs(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f) {
  if (m.spring_layout == SpringLayout::blocked) eval_springs_blocked(m, x, v, f);
  else eval_springs_gather(m, x, v, f);
}

Real max_spring_strain(const Model& m, std::span<const Vec3> x) {
  const auto over = [&](Index begin, Index end) {
    return tbb::parallel_reduce(
        tbb::blocked_range<Index>(begin, end, 4 * particle_grain), Real(0),
        [&](const tbb::blocked_range<Index>& r, Real best) {
          for (Index s = r.begin(); s != r.end(); ++s) {
            const Real len = (x[m.spring_b[s]] - x[m.spring_a[s]]).norm();
            best = std::max(best, (len - m.spring_rest[s]) / m.spring_rest[s]);
          }
          return best;
        },
        [](Real a, Real b) { return std::max(a, b); });
  };
  if (m.cloths.empty()) return over(0, m.spring_count);
  Real best = 0;
  for (const ClothInfo& c : m.cloths) best = std::max(best, over(c.spring_begin, c.spring_end - c.bend_springs));
  return best;
}

}  // namespace clothsim
