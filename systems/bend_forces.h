#pragma once
// Dihedral-angle bending (Bridson, Marino & Fedkiw 2003 §4.1; Grinspun et al. 2003): the force of each hinge is
// minus the exact gradient of its energy E = k (theta - theta0)^2 (core/hinges.h). Undamped: the springs'
// damping and air damping remain. The implicit integrator also puts each hinge's Gauss-Newton stiffness in its
// matrix (hinge_row below), which lifts the explicit step bound docs/stability.md gives for the other three.
#include <array>
#include <span>

#include "core/hinges.h"
#include "core/model.h"

namespace clothsim {

// d theta / d x for x1 = o1, x2 = o2, x3 = e0, x4 = e1: minus Bridson et al.'s (2003 §4.1) bending modes
// u1 = |E| N1/|N1|^2, u2 = |E| N2/|N2|^2, u3 = (x1-x4).E/|E| N1/|N1|^2 + (x2-x4).E/|E| N2/|N2|^2, u4 = -(x1-x3).E/|E|
// N1/|N1|^2 - (x2-x3).E/|E| N2/|N2|^2 (the sign follows hinge_angle's orientation; the unit test checks it
// against finite differences). The four sum to zero (translation) and are orthogonal to rotations.
inline std::array<Vec3, 4> hinge_angle_gradient(const Vec3& o1, const Vec3& o2, const Vec3& e0, const Vec3& e1,
                                                const HingeFrame& h) {
  const Vec3 g1 = h.n1 / h.n1_sq, g2 = h.n2 / h.n2_sq;  // N / |N|^2 = n / (2 A)
  const Real inv_e = 1 / h.e_len;
  const Real t1 = (o1 - e0).dot(h.e) * inv_e, t2 = (o2 - e0).dot(h.e) * inv_e;  // projections along the edge
  const Real s1 = (o1 - e1).dot(h.e) * inv_e, s2 = (o2 - e1).dot(h.e) * inv_e;
  return {-h.e_len * g1, -h.e_len * g2, -s1 * g1 - s2 * g2, t1 * g1 + t2 * g2};
}

// The forces on o1, o2, e0, e1 of a hinge of stiffness k and rest angle rest: -2 k (theta - theta0) d theta/d x.
// A hinge that has collapsed (zero edge or triangle area) exerts nothing.
inline std::array<Vec3, 4> hinge_forces(const Vec3& o1, const Vec3& o2, const Vec3& e0, const Vec3& e1, Real rest,
                                        Real k) {
  const HingeFrame h = hinge_frame(o1, o2, e0, e1);
  if (!hinge_live(h)) return {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  const Real c = -2 * k * hinge_angle_change(hinge_angle(h), rest);
  std::array<Vec3, 4> g = hinge_angle_gradient(o1, o2, e0, e1, h);
  for (Vec3& gi : g) gi *= c;
  return g;
}

// E = k (theta - theta0)^2 of one hinge, J (0 when collapsed).
inline Real hinge_energy(const Vec3& o1, const Vec3& o2, const Vec3& e0, const Vec3& e1, Real rest, Real k) {
  const HingeFrame h = hinge_frame(o1, o2, e0, e1);
  if (!hinge_live(h)) return 0;
  const Real d = hinge_angle_change(hinge_angle(h), rest);
  return k * d * d;
}

// Adds every hinge's forces to f: each hinge once into ws.hinge_force (in parallel, one writer each), then each
// particle gathers its entries in the CSR's fixed order, so the sums are the same bytes at any thread count.
void eval_hinges(const Model& model, std::span<const Vec3> x, std::span<Vec3> hinge_force, std::span<Vec3> f);

// The hinges in the backward-Euler matrix (systems/implicit_system.h). A hinge's Hessian is
// 2 k (g g^T + (theta - theta0) d^2 theta / dx^2), g = d theta / dx; its Gauss-Newton part K_h = 2 k g g^T keeps the
// first term only: positive semi-definite (the matrix stays so), exact at the rest angle, and it holds the hinge's
// one stiff mode, whose frequency sqrt(2 k g^T M^-1 g) bounds explicit steps (estimate_hinge_omega). The dropped
// term is of the order of theta - theta0 and acts along the triangles' planes, where the springs are stiff.
// build_hinge_jacobians writes u = sqrt(2 k) g at o1, o2, e0, e1 (4 * hinge_count; zero for a collapsed hinge),
// so K_h = u u^T and -df/dx = sum over hinges of u u^T.
void build_hinge_jacobians(const Model& m, std::span<const Vec3> x, std::span<Vec3> u);

// Calls fn(hinge, slot) for each hinge of particle i, in hinge order (slot 0..3: o1, o2, e0, e1).
template <class Fn>
inline void for_each_hinge_of(const Model& m, Index i, Fn&& fn) {
  for (Index k = m.particle_hinge_offset[i]; k < m.particle_hinge_offset[i + 1]; ++k)
    fn(m.particle_hinge_index[k] / 4, int(m.particle_hinge_index[k] % 4));
}
// u . p over one hinge's four particles.
inline Real hinge_combine(const Model& m, std::span<const Vec3> u, Index hinge, std::span<const Vec3> p) {
  const std::size_t b = 4 * std::size_t(hinge);
  const std::array<Index, 4> q = hinge_particles(m, hinge);
  return u[b].dot(p[q[0]]) + u[b + 1].dot(p[q[1]]) + u[b + 2].dot(p[q[2]]) + u[b + 3].dot(p[q[3]]);
}
// Row i of K = sum of u u^T times p, and its diagonal block: (K p)_i = sum over i's hinges of u_i (u . p).
inline Vec3 hinge_row(const Model& m, std::span<const Vec3> u, Index i, std::span<const Vec3> p) {
  Vec3 sum = Vec3::Zero();
  for_each_hinge_of(m, i, [&](Index h, int slot) { sum += hinge_combine(m, u, h, p) * u[4 * std::size_t(h) + slot]; });
  return sum;
}
inline Mat3 hinge_diagonal(const Model& m, std::span<const Vec3> u, Index i) {
  Mat3 d = Mat3::Zero();
  for_each_hinge_of(m, i, [&](Index h, int slot) {
    const Vec3& ui = u[4 * std::size_t(h) + slot];
    d += ui * ui.transpose();
  });
  return d;
}

// Total bending energy sum k (theta - theta0)^2, J, summed in a fixed order.
Real hinge_potential_energy(const Model& model, std::span<const Vec3> x);

// The largest single-hinge frequency at rest, rad/s: max over hinges of sqrt(2 k g^T M^-1 g), g = d theta/d x,
// the one non-zero eigenvalue of a hinge's M^-1 K alone (pinned particles removed). Hinges share particles, so
// the whole cloth's highest bending frequency is above it by a factor of order one (docs/stability.md).
Real estimate_hinge_omega(const Model& model, std::span<const Vec3> x);

}  // namespace clothsim
