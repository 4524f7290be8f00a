#pragma once
// Hooke springs with damping along the spring (Provot 1995 eq. 2-3; Baraff & Witkin 1998 §4).
#include <algorithm>
#include <cmath>
#include <span>

#include "core/model.h"
#include "core/spring_chunks.h"
#include "systems/parallel.h"

namespace clothsim {

// Force on particle a of a spring a-b: f = [ke (|d| - rest) + kd (v_b - v_a).d/|d|] d/|d|, d = x_b - x_a,
// from the components of d and dv = v_b - v_a. Particle b receives -f. A zero-length spring has no direction
// and exerts nothing. One expression shared by the scalar and the vectorised kernels, so they round alike.
struct SpringLane {
  Real fx, fy, fz;
};
inline SpringLane spring_force_lane(Real dx, Real dy, Real dz, Real dvx, Real dvy, Real dvz, Real rest, Real ke,
                                    Real kd) {
  const Real len = std::sqrt(dx * dx + dy * dy + dz * dz);
  // One division, not three: division and sqrt bound this kernel (docs/performance.md, "Roofline").
  const Real inv_len = 1 / len;
  const Real nx = inv_len * dx, ny = inv_len * dy, nz = inv_len * dz;
  const Real mag = ke * (len - rest) + kd * (dvx * nx + dvy * ny + dvz * nz);
  const bool live = len > 0;
  return {live ? mag * nx : 0.0, live ? mag * ny : 0.0, live ? mag * nz : 0.0};
}

inline Vec3 spring_force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb, Real rest, Real ke,
                         Real kd) {
  const SpringLane f = spring_force_lane(xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2], vb[0] - va[0],
                                         vb[1] - va[1], vb[2] - va[2], rest, ke, kd);
  return Vec3(f.fx, f.fy, f.fz);
}

// f[i] = sum of the spring forces on particle i (overwrites f), in the model's spring_layout.
void eval_springs(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f);
// The gather layout, and two-phase (each spring once into a per-spring buffer the caller owns, then a gather):
// callable directly so the benchmarks can compare them. No model selects two-phase: blocked computes each spring
// once without the buffer (docs/performance.md, "Spring-force layouts").
void eval_springs_gather(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f);
void eval_springs_two_phase(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v,
                            std::span<Vec3> f, std::span<Vec3> spring_force);
// The second phase of two_phase: f[i] = sum of the per-spring forces on particle i, in CSR order.
void gather_spring_forces(const Model& model, std::span<const Vec3> spring_force, std::span<Vec3> f);

// Blocked layout: each pass of model.spring_pass_chunk scatters its chunks in parallel; a chunk zeroes f of the
// particles it opens before its springs (core/spring_chunks.h). Sums in (pass, spring) order, not the CSR's:
// equal to gather up to rounding, and the same bytes at any thread count.
void eval_springs_blocked(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f);

// The forces on spring_a of springs [begin, end) (at most spring_block_size), as structure-of-arrays lanes.
struct SpringLanes {
  alignas(64) Real fx[spring_block_size];
  alignas(64) Real fy[spring_block_size];
  alignas(64) Real fz[spring_block_size];
};
void eval_spring_block(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, Index begin,
                       Index end, SpringLanes& out);

// One chunk of the blocked layout: zeroes f of the particles it opens, adds its springs in order, and after
// each block calls close(i) for the particles it closes that no later spring of the chunk touches.
template <class Close>
void scatter_spring_chunk(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f,
                          Index chunk, Close&& close) {
  for (Index r = m.spring_chunk_open_offset[chunk]; r < m.spring_chunk_open_offset[chunk + 1]; ++r)
    std::fill(f.begin() + m.spring_chunk_open_range[2 * r], f.begin() + m.spring_chunk_open_range[2 * r + 1],
              Vec3::Zero());
  // Cursor over the chunk's close ranges.
  Index r = m.spring_chunk_close_offset[chunk];
  const Index r_end = m.spring_chunk_close_offset[chunk + 1];
  Index i = r < r_end ? m.spring_chunk_close_range[2 * r] : 0, closed = 0;
  // Grid and mesh orders give a spring's first end to several springs in a row: its force is held in registers
  // until the first end changes (the same additions in the same order as f[a] += f_s, without a store-to-load
  // round trip per spring).
  const Index begin = m.spring_chunk_offset[chunk], end = m.spring_chunk_offset[chunk + 1];
  Index held = m.spring_a[begin];
  Vec3 sum = f[held];
  SpringLanes lanes;
  for (Index block = begin; block < end; block += spring_block_size) {
    const Index stop = std::min(block + spring_block_size, end);
    eval_spring_block(m, x, v, block, stop, lanes);
    for (Index s = block; s < stop; ++s) {
      const Vec3 fs(lanes.fx[s - block], lanes.fy[s - block], lanes.fz[s - block]);
      const Index a = m.spring_a[s], b = m.spring_b[s];
      if (a != held) {
        f[held] = sum;
        held = a;
        sum = f[a];
      }
      sum += fs;
      if (b == held) sum -= fs;
      else f[b] -= fs;
    }
    f[held] = sum;
    for (const Index ready = m.spring_block_close[block / spring_block_size]; closed < ready; ++closed) {
      close(i);
      if (++i == m.spring_chunk_close_range[2 * r + 1] && ++r < r_end) i = m.spring_chunk_close_range[2 * r];
    }
    sum = f[held];  // close() may have replaced a closed particle's force (nothing adds to it any more)
  }
}

// eval_springs_blocked, then close(i) once per particle as soon as f[i] is final: inside the chunk that closes
// particle i, right after the block of its last spring, while its data is in cache. close(i) may overwrite x[i]
// and v[i] (no spring reads them after) and must not touch another particle. The bytes of f are those of
// eval_springs_blocked.
template <class Close>
void eval_springs_blocked_then(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v,
                               std::span<Vec3> f, Close&& close) {
  const Index passes = Index(m.spring_pass_offset.size()) - 1;
  for (Index p = 0; p < passes; ++p) {
    const Index first = m.spring_pass_offset[p];
    // One chunk per task: chunks of a pass touch disjoint particles, and a chunk adds in spring order.
    parallel_over(m.spring_pass_offset[p + 1] - first, 1,
                  [&](Index k) { scatter_spring_chunk(m, x, v, f, m.spring_pass_chunk[first + k], close); });
  }
  // Particles no chunk spans (no springs, or outside every span): no spring force.
  const Index rest = Index(m.spring_chunk_offset.size()) - 1;
  for (Index r = m.spring_chunk_close_offset[rest]; r < m.spring_chunk_close_offset[rest + 1]; ++r) {
    const Index begin = m.spring_chunk_close_range[2 * r];
    parallel_over(m.spring_chunk_close_range[2 * r + 1] - begin, particle_grain, [&](Index k) {
      f[begin + k] = Vec3::Zero();
      close(begin + k);
    });
  }
}

// Largest strain (|d| - rest)/rest over the stretch springs, 0 at least: a maximum, so exact at any thread count.
// A mesh cloth's bend springs are left out (ClothInfo::bend_springs): their length measures bending, and across a
// hinge folded flat at rest (a knife pleat) one is a fraction of a millimetre long, so that the smallest opening of
// the fold reads as tens of percent.
Real max_spring_strain(const Model& model, std::span<const Vec3> x);

}  // namespace clothsim
