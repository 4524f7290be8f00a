#pragma once
// Stitches: zero-rest-length springs that sew vertex a to the point (1 - w) x_b + w x_c of another panel
// (Codim-IPC's stitch records; Blender's sewing springs). With c = (1, -(1 - w), -w) over (a, b, c) the gap is
// g = sum_k c_k x_k, linear in x, and a stitch's force on its particle k is
//   f_k = -c_k (ke (g - g*(t)) + kd (g' - g*'(t))),
// so df/dx = -ke c c^T (x) I and df/dv = -kd c c^T (x) I: constant, symmetric, and -df/dx positive semi-definite,
// which the backward-Euler matrix takes as it is (Baraff & Witkin 1998 eq. 15-16; no per-step linearisation).
// Sewing speed is bounded by the target g*(t) = g0 max(0, 1 - t / T), T = |g0| / sewSpeed: the target gap
// shrinks from the start gap g0 to zero at sewSpeed m/s, so a stitch never pulls towards a point nearer than
// the target. The stitch pass (apply_stitch_limit) then keeps |g - g*(t)| <= stitch_tolerance after each step.
// docs/garments.md gives the figures.
#include <array>
#include <span>

#include "core/model.h"

namespace clothsim {

// Largest |g - g*(t)| the stitch pass leaves, m.
inline constexpr Real stitch_tolerance = 5e-4;
inline constexpr int stitch_max_iterations = 100;

// Weights of the stitch's three particles in its gap: (1, -(1 - w), -w).
inline std::array<Real, 3> stitch_coefficients(Real w) { return {1, -(1 - w), -w}; }

inline std::array<Index, 3> stitch_particles(const Model& m, Index s) {
  return {m.stitch_a[s], m.stitch_b[s], m.stitch_c[s]};
}

// sum_k c_k y_k over the stitch's particles: the gap for positions, its rate for velocities.
inline Vec3 stitch_combine(const Model& m, Index s, std::span<const Vec3> y) {
  const Real w = m.stitch_w[s];
  return y[m.stitch_a[s]] - (1 - w) * y[m.stitch_b[s]] - w * y[m.stitch_c[s]];
}

// Target gap g*(t) and its rate, for t seconds after the start.
inline Vec3 stitch_target(const Model& m, Index s, Real t) {
  const Real close = m.stitch_close_time[s];
  return t < close ? Vec3((1 - t / close) * m.stitch_gap0[s]) : Vec3(Vec3::Zero());
}
inline Vec3 stitch_target_rate(const Model& m, Index s, Real t) {
  const Real close = m.stitch_close_time[s];
  return t < close ? Vec3(-m.stitch_gap0[s] / close) : Vec3(Vec3::Zero());
}

// The stitch's force on a particle of coefficient 1, at time t: -(ke (g - g*) + kd (g' - g*')).
inline Vec3 stitch_force(const Model& m, Index s, std::span<const Vec3> x, std::span<const Vec3> v, Real t) {
  return -(m.stitch_ke[s] * (stitch_combine(m, s, x) - stitch_target(m, s, t)) +
           m.stitch_kd[s] * (stitch_combine(m, s, v) - stitch_target_rate(m, s, t)));
}

// Adds every stitch's forces to f (N). Serial in stitch order: same bytes at any thread count; stitches are few
// next to springs.
void eval_stitches(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Real t, std::span<Vec3> f);

// The stitches' part of the backward-Euler matrix A = M - h df/dv - h^2 df/dx at particle i:
// (h kd + h^2 ke) c_i c^T (x) I. stitch_diagonal gives its diagonal coefficient, stitch_row its row times p
// (p zero on pinned particles), stitch_dfdx_times its (df/dx) v.
inline Real stitch_diagonal(const Model& m, Index i, Real h) {
  Real d = 0;
  for (Index k = m.particle_stitch_offset[i]; k < m.particle_stitch_offset[i + 1]; ++k) {
    const Index s = m.particle_stitch_index[k] / 3;
    const Real c = stitch_coefficients(m.stitch_w[s])[m.particle_stitch_index[k] % 3];
    d += (h * m.stitch_kd[s] + h * h * m.stitch_ke[s]) * c * c;
  }
  return d;
}
inline Vec3 stitch_row(const Model& m, Index i, Real h, std::span<const Vec3> p) {
  Vec3 sum = Vec3::Zero();
  for (Index k = m.particle_stitch_offset[i]; k < m.particle_stitch_offset[i + 1]; ++k) {
    const Index s = m.particle_stitch_index[k] / 3;
    const Real c = stitch_coefficients(m.stitch_w[s])[m.particle_stitch_index[k] % 3];
    sum += ((h * m.stitch_kd[s] + h * h * m.stitch_ke[s]) * c) * stitch_combine(m, s, p);
  }
  return sum;
}
inline Vec3 stitch_dfdx_times(const Model& m, Index i, std::span<const Vec3> v) {
  Vec3 sum = Vec3::Zero();
  for (Index k = m.particle_stitch_offset[i]; k < m.particle_stitch_offset[i + 1]; ++k) {
    const Index s = m.particle_stitch_index[k] / 3;
    const Real c = stitch_coefficients(m.stitch_w[s])[m.particle_stitch_index[k] % 3];
    sum -= (m.stitch_ke[s] * c) * stitch_combine(m, s, v);
  }
  return sum;
}

// Largest |g - g*(t)| over the stitches, m; 0 without stitches.
Real stitch_excess(const Model& m, std::span<const Vec3> x, Real t);

// After a step of h ending at time t: Gauss-Seidel projections in stitch order, each moving a stitch with
// |g - g*(t)| > stitch_tolerance back to |g - g*| = stitch_tolerance / 2, split over its particles by inverse
// mass and coefficient (Provot 1995 §5, as the strain limit), velocities changed by the same displacement / h;
// until every stitch is within stitch_tolerance or stitch_max_iterations sweeps. Returns the sweeps taken.
int apply_stitch_limit(const Model& m, State& out, Real h, Real t);

}  // namespace clothsim
