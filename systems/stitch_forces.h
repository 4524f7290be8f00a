#pragma once
// Stitches sew vertex a to the point (1 - w) x_b + w x_c of another panel (Codim-IPC's stitch records; Blender's
// sewing springs). With c = (1, -(1 - w), -w) over (a, b, c) the gap is g = sum_k c_k x_k, linear in x.
// While sewing, a stitch is a thread on the gap: it pulls along the gap when the gap is longer than its length,
// and is slack otherwise. Its length follows a target L*(t) = |g0| max(0, 1 - t / T), T = |g0| / sewSpeed, that
// shrinks from the start gap to zero at sewSpeed. Acting along the gap only, a seam sewn over a shoulder can
// slide round it instead of being dragged along the straight line between its panels (the start gap's
// direction) into the body; pulling only, neighbouring stitches with different schedules cannot push a seam
// apart (a lower bound on |g| from one schedule and an upper bound from the next one over are incompatible;
// upper bounds alone are all met by the sewn garment). Each step of h the thread's length is
// L = max(L*(t + h), |g(x0)| - u h), x0 the positions at the step's start and u the closing speed the thread
// allows: at most sewSpeed, gained and lost at stitch_acceleration (set_stitch_rest). So a gap is never pulled
// closed faster than sewSpeed; one that a contact or the strain limit holds behind its schedule is not yanked
// shut (through the body) in one step, and catches up once the target reaches zero. With n = g / |g|, taut (|g| > L), the force on
// a particle of coefficient 1 is
//   f = -(ke (|g| - L) + kd (n . g' + u)) n,
// -df/dg = ke (n n^T + (1 - L / |g|) (I - n n^T)) and -df/dg' = kd n n^T: positive semi-definite, the damping's
// x-derivative dropped, as for springs. Once L = 0 (sewn and within sewSpeed h) it is a zero-rest-length spring,
// f = -(ke g + kd g'), with constant Jacobians ke I and kd I. The backward-Euler matrix takes
// c c^T (x) (h Kv + h^2 Kx) for each stitch (Baraff & Witkin 1998 eq. 15-16), linearised at the start of the
// step. After each step the stitch pass (apply_stitch_limit) shortens each gap longer than L.
// docs/garments.md gives the figures.
#include <algorithm>
#include <array>
#include <limits>
#include <span>

#include "core/model.h"
#include "systems/spring_jacobian.h"

namespace clothsim {

// Largest error the stitch pass leaves about a gap's schedule, m; about a clamped rest length, a micrometre.
inline constexpr Real stitch_tolerance = 5e-4;
inline constexpr Real stitch_clamped_tolerance = 1e-6;
inline constexpr int stitch_max_iterations = 100;
// Rounds of the stitch pass and the strain limit a step alternates while the stitch pass still moves a gap (the
// strain limit reopens gaps whose panels are short of their partners): on the mannequin sewing, 10 rounds leave
// 75 stitches over 1 mm against 118 with one (docs/garments.md).
inline constexpr int stitch_strain_rounds = 10;
// The same after the collide stage, where the strain limit holds the collider contacts on their planes and each
// round costs more sweeps: on the Rumba, 3 rounds leave a median 109 stitches over 1 mm a frame at 1.5 s a frame,
// 10 rounds 87 at 2.2-2.7 s, 1 round 154 at 1.3 s (docs/garments.md).
inline constexpr int stitch_strain_rounds_after_collide = 3;
// The most a thread speeds up or slows down the closing of its gap, m/s^2: a seam starts closing, catches up
// after a contact lets it go, and comes to rest at its partner over a few centimetres, not in one step (which
// would jerk its whole panel to sewSpeed and stretch the cloth round the seam by tens of percent).
inline constexpr Real stitch_acceleration = 2;

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

// The target length L*(t), t seconds after the start.
inline Real stitch_target_length(const Model& m, Index s, Real t) {
  const Real close = m.stitch_close_time[s];
  return t < close ? (1 - t / close) * m.stitch_gap0[s].norm() : Real(0);
}
// The stitch's sewing speed, m/s (infinite for a stitch that starts closed).
inline Real stitch_speed(const Model& m, Index s) {
  const Real close = m.stitch_close_time[s];
  return close > 0 ? m.stitch_gap0[s].norm() / close : std::numeric_limits<Real>::infinity();
}

// Each stitch's thread for a step of h from (x0, v0) ending at time t_end: its length
// rest = max(L*(t_end), |g(x0)| - u h), u = min(sewSpeed, u0 + stitch_acceleration h,
// sqrt(2 stitch_acceleration |g(x0)|)) with u0 the speed the gap closes at (u = sewSpeed once L* = 0), and the
// speed it shortens at, pull = (|g(x0)| - rest) / h (stitch_count each).
void set_stitch_rest(const Model& m, std::span<const Vec3> x0, std::span<const Vec3> v0, Real t_end, Real h,
                     std::span<Real> rest, std::span<Real> pull);

// A stitch's force on a particle of coefficient 1 and its Jacobian blocks -df/dg, -df/dg' at (x, v), for its
// step's thread (length rest, shortening at pull). A taut thread's blocks are those of a spring of that rest
// length across the gap (spring_jacobian).
struct StitchTerms {
  Vec3 force = Vec3::Zero();
  SpringJacobian jac{Mat3::Zero(), Mat3::Zero()};
};
inline StitchTerms stitch_terms(const Model& m, Index s, std::span<const Vec3> x, std::span<const Vec3> v, Real rest,
                                Real pull) {
  const Vec3 g = stitch_combine(m, s, x), rate = stitch_combine(m, s, v);
  const Real ke = m.stitch_ke[s], kd = m.stitch_kd[s];
  StitchTerms out;
  if (rest == 0) {
    out.force = -(ke * g + kd * rate);
    out.jac = {ke * Mat3::Identity(), kd * Mat3::Identity()};
    return out;
  }
  const Real l = g.norm();
  if (!(l > rest)) return out;  // slack: a thread does not push
  const Vec3 n = g / l;
  out.force = -(ke * (l - rest) + kd * (n.dot(rate) + pull)) * n;
  out.jac = spring_jacobian(Vec3::Zero(), g, rest, ke, kd);
  return out;
}

// Adds every stitch's forces to f (N), for the step's threads (set_stitch_rest). Serial in stitch order: same
// bytes at any thread count; stitches are few next to springs.
void eval_stitches(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::span<const Real> rest,
                   std::span<const Real> pull, std::span<Vec3> f);

// Each stitch's blocks for the step's matrix at (x, v) and the step's threads: ws.stitch_kx = Kx and
// ws.stitch_block = h Kv + h^2 Kx (stitch_count).
void build_stitch_blocks(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Real h, Workspace& ws);

// The stitches' part of A = M - h df/dv - h^2 df/dx at particle i: sum over its stitches of
// c_i c^T (x) ws.stitch_block. stitch_diagonal gives its diagonal block, stitch_row its row times p (p zero on
// pinned particles), stitch_dfdx_times its (df/dx) v.
// Calls fn(s, c) for each stitch s of particle i, in stitch order, c the particle's coefficient in it.
template <class Fn>
inline void for_each_stitch_of(const Model& m, Index i, Fn&& fn) {
  for (Index k = m.particle_stitch_offset[i]; k < m.particle_stitch_offset[i + 1]; ++k) {
    const Index s = m.particle_stitch_index[k] / 3;
    fn(s, stitch_coefficients(m.stitch_w[s])[m.particle_stitch_index[k] % 3]);
  }
}
inline Sym3 stitch_diagonal(const Model& m, const Workspace& ws, Index i) {
  Sym3 d;
  for_each_stitch_of(m, i, [&](Index s, Real c) { d += Sym3::from((c * c) * ws.stitch_block[s].full()); });
  return d;
}
inline Vec3 stitch_row(const Model& m, const Workspace& ws, Index i, std::span<const Vec3> p) {
  Vec3 sum = Vec3::Zero();
  for_each_stitch_of(m, i, [&](Index s, Real c) { sum += c * (ws.stitch_block[s] * stitch_combine(m, s, p)); });
  return sum;
}
inline Vec3 stitch_dfdx_times(const Model& m, const Workspace& ws, Index i, std::span<const Vec3> v) {
  Vec3 sum = Vec3::Zero();
  for_each_stitch_of(m, i, [&](Index s, Real c) { sum -= c * (ws.stitch_kx[s] * stitch_combine(m, s, v)); });
  return sum;
}

// After a step of h ending at time t, each gap longer than its thread is shortened: to within
// stitch_tolerance / 2 of L*(t) where the thread's length is L* (beyond stitch_tolerance), and to a length
// clamped above L* exactly (beyond stitch_clamped_tolerance), so a held gap is shortened by sewSpeed h a step at
// most. A gap shorter than its thread is left alone. Gauss-Seidel projections in stitch order move each gap along
// itself, split over its particles by inverse mass and coefficient (Provot 1995 §5, as the strain limit),
// velocities changed by the same displacement / h; until no gap is moved or stitch_max_iterations sweeps.
// Returns the sweeps taken.
int apply_stitch_limit(const Model& m, std::span<const Real> rest, State& out, Real h, Real t);

}  // namespace clothsim
