#pragma once
// Dihedral-angle bending hinges (Bridson, Marino & Fedkiw 2003; Grinspun et al. 2003, "Discrete shells"): each
// interior manifold edge e0-e1 with the two vertices o1, o2 opposite it, its rest angle and its stiffness. The
// energy of a hinge is E = k (theta - theta0)^2 with k = (D / 6) 3 |e|^2 / (A1 + A2) from the rest mesh
// (docs/model.md derives the 1/6: a cylinder of radius R then stores D / (2 R^2) per unit area).
#include <array>
#include <cmath>
#include <numbers>
#include <span>

#include "core/math.h"
#include "core/model.h"

namespace clothsim {

struct Topology;

// Hinge h's particles in slot order: o1, o2, e0, e1 (the order of particle_hinge_index's slots).
inline std::array<Index, 4> hinge_particles(const Model& m, Index h) {
  return {m.hinge_o1[h], m.hinge_o2[h], m.hinge_e0[h], m.hinge_e1[h]};
}

// Hinge geometry in Bridson et al.'s (2003, §4.1) naming: x1 = o1, x2 = o2, x3 = e0, x4 = e1, the edge
// E = x4 - x3, and the two triangles' area normals N1 = (x1 - x3) x (x1 - x4), N2 = (x2 - x4) x (x2 - x3)
// (|Ni| = 2 Ai). theta is the signed angle from N1 to N2 about E, 0 for a flat hinge; it depends on positions
// only, so the meshes' triangle windings do not matter.
struct HingeFrame {
  Vec3 e, n1, n2;
  Real e_len = 0, n1_sq = 0, n2_sq = 0;
};
inline HingeFrame hinge_frame(const Vec3& o1, const Vec3& o2, const Vec3& e0, const Vec3& e1) {
  HingeFrame h;
  h.e = e1 - e0;
  h.n1 = (o1 - e0).cross(o1 - e1);
  h.n2 = (o2 - e1).cross(o2 - e0);
  h.e_len = h.e.norm();
  h.n1_sq = h.n1.squaredNorm();
  h.n2_sq = h.n2.squaredNorm();
  return h;
}
// A hinge with a zero-length edge or a zero-area triangle has no angle: it is skipped (its force is zero).
inline bool hinge_live(const HingeFrame& h) { return h.e_len > 0 && h.n1_sq > 0 && h.n2_sq > 0; }
// atan2 of the sine and cosine, both scaled by |N1| |N2| (no normalisation needed), in (-pi, pi].
inline Real hinge_angle(const HingeFrame& h) {
  return std::atan2(h.n1.cross(h.n2).dot(h.e) / h.e_len, h.n1.dot(h.n2));
}
// theta - theta0 wrapped into [-pi, pi): a hinge whose rest is near +-pi does not jump by 2 pi when it crosses.
inline Real hinge_angle_change(Real theta, Real rest) {
  Real d = theta - rest;
  if (d >= std::numbers::pi) d -= 2 * std::numbers::pi;
  else if (d < -std::numbers::pi) d += 2 * std::numbers::pi;
  return d;
}

// Appends the hinges of one cloth (its topology, particles numbered from base) to the model: rest angles and
// stiffness k from the rest positions `rest` (indexed globally) for bending modulus D (N m). Hinges whose rest
// edge or a rest triangle has zero length or area are left out: their weight 3|e|^2/(A1 + A2) is undefined.
void append_hinges(Model& m, const Topology& topo, Index base, std::span<const Vec3> rest, Real bend_modulus);

}  // namespace clothsim
