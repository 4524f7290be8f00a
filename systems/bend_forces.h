#pragma once
// Dihedral-angle bending (Bridson, Marino & Fedkiw 2003 §4.1; Grinspun et al. 2003): the force of each hinge is
// minus the exact gradient of its energy E = k (theta - theta0)^2 (core/hinges.h). Undamped: the springs'
// damping and air damping remain. The implicit integrator takes it explicitly, on the right-hand side only
// (Bridson et al. 2003 do the same for bending; docs/stability.md gives the step bound that follows).
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

// Total bending energy sum k (theta - theta0)^2, J, summed in a fixed order.
Real hinge_potential_energy(const Model& model, std::span<const Vec3> x);

// The largest single-hinge frequency at rest, rad/s: max over hinges of sqrt(2 k g^T M^-1 g), g = d theta/d x,
// the one non-zero eigenvalue of a hinge's M^-1 K alone (pinned particles removed). Hinges share particles, so
// the whole cloth's highest bending frequency is above it by a factor of order one (docs/stability.md).
Real estimate_hinge_omega(const Model& model, std::span<const Vec3> x);

}  // namespace clothsim
