#pragma once
// Hooke springs with damping along the spring (Provot 1995 eq. 2-3; Baraff & Witkin 1998 §4).
#include <cmath>
#include <span>

#include "core/model.h"

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
  // One division, not three: division and sqrt bound this kernel (docs/performance.md, roofline).
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
void eval_springs(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f,
                  std::span<Vec3> spring_scratch);
// The two layouts, callable directly so the benchmark can compare them.
void eval_springs_gather(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f);
void eval_springs_two_phase(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v,
                            std::span<Vec3> f, std::span<Vec3> spring_force);
// The second phase of two_phase: f[i] = sum of the per-spring forces on particle i, in CSR order.
void gather_spring_forces(const Model& model, std::span<const Vec3> spring_force, std::span<Vec3> f);

// Blocked layout: f zeroed, then each pass of model.spring_pass_chunk scatters its chunks in parallel. Sums in
// (pass, spring) order, not the CSR's: equal to gather up to rounding, and the same bytes at any thread count.
void eval_springs_blocked(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f);

// Largest strain (|d| - rest)/rest over all springs: a maximum, so exact at any thread count.
Real max_spring_strain(const Model& model, std::span<const Vec3> x);

}  // namespace clothsim
