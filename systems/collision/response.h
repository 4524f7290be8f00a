#pragma once
// Per-contact responses (Bridson, Fedkiw & Anderson 2002 §7) and the fixed-point per-particle accumulators that
// average several contacts on one vertex with the same bytes at any thread count. The per-element maths is inline
// and free of threads; below it, the responses of each contact kind the proximity and continuous passes find, and
// the clear/apply of the accumulators around a pass (response.cpp).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>

#include "core/model.h"
#include "systems/collision/proximity.h"

namespace clothsim {

// 2^30 units per m or m/s: 1e-9 resolution, and 1e6 (the clamp) times a thousand contacts still fits in 63 bits.
inline constexpr Real fixed_scale = 1073741824.0;

inline std::int64_t to_fixed(Real x) { return std::llround(std::clamp(x, Real(-1e6), Real(1e6)) * fixed_scale); }

// Adds a velocity and position change for particle i and counts one contact; integer atomics, so the sum is
// exact and independent of order.
inline void accumulate_contact(CollisionScratch& s, Index i, const Vec3& dv, const Vec3& dx) {
  for (int k = 0; k < 3; ++k) {
    std::atomic_ref<std::int64_t>(s.acc_dv[3 * std::size_t(i) + k]).fetch_add(to_fixed(dv[k]), std::memory_order_relaxed);
    std::atomic_ref<std::int64_t>(s.acc_dx[3 * std::size_t(i) + k]).fetch_add(to_fixed(dx[k]), std::memory_order_relaxed);
  }
  std::atomic_ref<std::int32_t>(s.acc_count[i]).fetch_add(1, std::memory_order_relaxed);
}

// Velocity change of a particle touching a collider point moving at v_col, normal n (pointing to the free side):
// the normal relative velocity is reversed and scaled by the restitution e, the tangential one reduced by
// Coulomb friction: it sticks while the tangential change stays within mu times the normal change
// (Bridson et al. 2002 §7.2, eq. for v_t). Zero when the particle already separates.
inline Vec3 collider_velocity_change(const Vec3& v, const Vec3& v_col, const Vec3& n, Real e, Real mu) {
  const Vec3 rel = v - v_col;
  const Real vn = rel.dot(n);
  if (!(vn < 0)) return Vec3::Zero();
  const Real dvn = -(1 + e) * vn;
  const Vec3 vt = rel - vn * n;
  const Real vt_len = vt.norm();
  Vec3 dv = dvn * n;
  if (vt_len <= mu * dvn) dv -= vt;
  else dv -= (mu * dvn / vt_len) * vt;
  return dv;
}
// With the contact filter on, a cloth vertex this close to a collider, in thicknesses, is held in the next solve
// though not pushed: the collide stage leaves a resting vertex at exactly the thickness, where round-off decides
// whether the next stage finds it, and a hold on every other step only would let it fall in and be pushed out
// again on the others.
inline constexpr Real contact_hold_reach = 1.1;
inline Real collider_reach(const CollisionScratch& s, Real thickness) {
  return s.acc_hold.empty() ? thickness : contact_hold_reach * thickness;
}
// Adds a collider contact of particle i (unit normal n to the free side, the collider's velocity there, the
// contact's friction) to the contact filter's sums, where the filter is on.
inline void note_collider_contact(CollisionScratch& s, Index i, const Vec3& n, const Vec3& v_col, Real mu) {
  if (s.acc_hold.empty()) return;
  const Real values[7] = {n[0], n[1], n[2], v_col[0], v_col[1], v_col[2], mu};
  for (int k = 0; k < 7; ++k)
    std::atomic_ref<std::int64_t>(s.acc_hold[7 * std::size_t(i) + k]).fetch_add(to_fixed(values[k]), std::memory_order_relaxed);
  std::atomic_ref<std::int32_t>(s.acc_hold_count[i]).fetch_add(1, std::memory_order_relaxed);
}
// Position change that goes with a velocity change dv over a step h (x = x0 + h v, as the integrators move
// positions), plus the push along n that leaves the particle at distance `thickness` on the safe side.
inline Vec3 collider_position_change(const Vec3& dv, const Vec3& n, Real d, Real thickness, Real h) {
  const Real d_after = d + h * dv.dot(n);
  return h * dv + std::max(Real(0), thickness - d_after) * n;
}

// Speed, beyond the approach a contact stops, at which a cloth vertex is pushed from a collider's surface out to
// the thickness, m/s: a garment that starts in contact with the body (closer than its thickness, at rest) eases
// out instead of jumping the whole thickness in one step, which would stretch the springs round it
// (docs/garments.md, "Initial contact").
inline constexpr Real collider_separation_speed = 0.1;

// collider_position_change for a cloth vertex: back to the surface at once when it ended behind it, then at most
// (dv.n + collider_separation_speed) h further towards the thickness.
inline Vec3 eased_position_change(const Vec3& dv, const Vec3& n, Real d, Real thickness, Real h) {
  const Real dvn = dv.dot(n);
  const Real d_after = d + h * dvn;
  const Real reach = std::max(Real(0), -d_after) + (std::max(Real(0), dvn) + collider_separation_speed) * h;
  return h * dv + std::max(Real(0), std::min(thickness - d_after, reach)) * n;
}

// Adds sum wt_i v_i to rel and sum wt_i^2 inv_m_i to denom over the pair's particles: the relative velocity of a
// cloth-cloth (or cloth-collider-edge) pair and the effective inverse mass its impulse divides by.
inline void weighted_velocity(const Index* p, const Real* wt, int count, const Model& m, const std::vector<Vec3>& v,
                              Vec3& rel, Real& denom) {
  for (int k = 0; k < count; ++k) {
    rel += wt[k] * v[p[k]];
    denom += wt[k] * wt[k] * m.particle_inv_mass[p[k]];
  }
}

// The relative velocity change of a pair: dvn along n, and Coulomb friction taking at most mu dvn off the
// tangential part of rel (vn = rel . n).
inline Vec3 normal_change_with_friction(const Vec3& rel, Real vn, const Vec3& n, Real dvn, Real mu) {
  const Vec3 vt = rel - vn * n;
  const Real vt_len = vt.norm();
  Vec3 change = dvn * n;
  if (vt_len > 0) change -= std::min(vt_len, mu * dvn) / vt_len * vt;
  return change;
}

// Stiffness of a contact's repulsion spring: the stretch stiffness of its particles, each side of the pair
// interpolated by its weights (k = sum |wt_i| k_i / sum |wt_i|; both sides' |wt| sum to 1, so this is the mean of
// the two sides' interpolated stiffness).
inline Real contact_stiffness(const Index* p, const Real* wt, int count, const Model& m) {
  Real k = 0, weight = 0;
  for (int i = 0; i < count; ++i) {
    k += std::abs(wt[i]) * m.particle_stiffness[p[i]];
    weight += std::abs(wt[i]);
  }
  return weight > 0 ? k / weight : 0;
}

// The relative normal velocity change of a pair whose relative normal velocity is vn, closer than the thickness
// by `overlap` (> 0), over a step h, with effective inverse mass denom = sum wt_i^2 inv_m_i and repulsion spring
// k (Bridson, Fedkiw & Anderson 2002 §7.2): an inelastic change that stops an approach, then, while the pair
// separates slower than 0.1 overlap / h, a repulsion impulse I_r = min(h k overlap, (0.1 overlap / h - vn) / denom)
// -- the spring's impulse over one step, never more than the velocity that closes a tenth of the overlap. From
// rest this gives the pair at most min(h^2 k denom, 0.01 / (h^2 k denom)) <= 0.1 times the spring energy
// k overlap^2 / 2 (kinetic energy I_r^2 denom / 2).
inline Real repulsion_change(Real vn, Real overlap, Real denom, Real k, Real h) {
  const Real stop = std::max(Real(0), -vn);
  const Real vn_after = vn + stop, target = Real(0.1) * overlap / h;
  if (!(vn_after < target)) return stop;
  return stop + std::min(h * k * overlap * denom, target - vn_after);
}

// Cloth-cloth impulse over up to four particles with signed weights wt (relative velocity sum wt_i v_i, normal
// n pointing the way that relative velocity must grow) closer than the thickness (end-of-step distance d,
// negative when the pair crossed): the inelastic stop and spring-capped repulsion of repulsion_change, with k
// from contact_stiffness, and Coulomb friction. The impulse J satisfies sum wt_i^2 inv_m_i J = required change;
// with equal masses this is Bridson et al.'s 2I/(1 + sum w^2) scaling (§7.1). Returns false when no change is
// needed.
inline bool cloth_impulse(const Index* p, const Real* wt, int count, const Model& m, const std::vector<Vec3>& v,
                          const Vec3& n, Real d, Real thickness, Real mu, Real h, Vec3* dv_out) {
  Vec3 rel = Vec3::Zero();
  Real denom = 0;
  weighted_velocity(p, wt, count, m, v, rel, denom);
  if (!(denom > 0) || !(d < thickness)) return false;
  const Real vn = rel.dot(n);
  const Real dvn = repulsion_change(vn, thickness - d, denom, contact_stiffness(p, wt, count, m), h);
  if (!(dvn > 0)) return false;
  const Vec3 j = normal_change_with_friction(rel, vn, n, dvn, mu) / denom;
  for (int k = 0; k < count; ++k) dv_out[k] = wt[k] * m.particle_inv_mass[p[k]] * j;
  return true;
}

// The continuous pass's response to a pair that crossed during the step (up to four cloth particles with signed
// weights wt; v_fixed: the velocity of an immovable other side, a collider edge's point): an inelastic impulse
// that stops the approach along n (relative normal velocity to zero, Coulomb friction on the tangential part),
// and a position-only push that leaves the pair `thickness` apart along n at the end of the step, both spread
// over the particles by wt_i inv_m_i / sum wt^2 inv_m (Bridson et al. 2002 §7.1). A velocity that restored the
// whole distance would fling the cloth away (thickness / step: metres per second); the push does not.
inline bool inelastic_separation(const Index* p, const Real* wt, int count, const Model& m,
                                 const std::vector<Vec3>& v, const Vec3& v_fixed, const Vec3& n, Real d,
                                 Real thickness, Real mu, Real h, Vec3* dv_out, Vec3* dx_out) {
  Vec3 rel = -v_fixed;
  Real denom = 0;
  weighted_velocity(p, wt, count, m, v, rel, denom);
  if (!(denom > 0) || !(d < thickness)) return false;
  const Real vn = rel.dot(n), dvn = std::max(Real(0), -vn);
  const Vec3 change = normal_change_with_friction(rel, vn, n, dvn, mu);
  const Real push = std::max(Real(0), thickness - d - h * dvn);
  for (int k = 0; k < count; ++k) {
    const Real share = wt[k] * m.particle_inv_mass[p[k]] / denom;
    dv_out[k] = share * change;
    dx_out[k] = h * dv_out[k] + share * push * n;
  }
  return true;
}

// Friction of a contact: the geometric mean of the two sides' Coulomb coefficients (Box2D's rule), so a side
// with friction 0 makes the contact frictionless and two equal sides keep their value (docs/scene-format.md,
// "Friction"). Restitution is the cloth's.
inline Real combine_friction(Real a, Real b) { return std::sqrt(a * b); }
inline Real collider_friction(const Model& m, Index i, Index collider) {
  return combine_friction(m.cloths[m.collision.particle_cloth[i]].friction, m.collision.colliders[collider].friction);
}
// Cloth particles a and b on the two sides of a cloth-cloth contact.
inline Real cloth_pair_friction(const Model& m, Index a, Index b) {
  const CollisionModel& c = m.collision;
  return combine_friction(m.cloths[c.particle_cloth[a]].friction, m.cloths[c.particle_cloth[b]].friction);
}
inline Real contact_friction(const Model& m, Index i, Index prim) {
  const CollisionModel& c = m.collision;
  if (prim >= m.tri_count) return collider_friction(m, i, c.mesh_tri_collider[prim - m.tri_count]);
  return cloth_pair_friction(m, i, m.tri_index[3 * prim]);
}

struct PrimCorners;  // systems/collision/broad_phase.h

// Zeroes the accumulators before a pass; apply_accumulated then adds each particle's mean change to out and
// returns the number of contacts accumulated (an exact integer sum: the same at any thread count).
void clear_accumulators(const Model& model, CollisionScratch& s);
std::int64_t apply_accumulated(const Model& model, State& out, CollisionScratch& s);

// One vertex-triangle contact, normal n towards the vertex's side, end-of-step distance d: the collider response
// for a collider triangle; for a cloth one, the spring-capped cloth impulse in the proximity pass and, in the
// continuous pass (`crossed`), the inelastic stop with a position-only push back to the thickness.
void respond_vertex_triangle(const Model& model, const State& out, CollisionScratch& s, Index i, Index prim,
                             const PrimCorners& t, const Real* w, const Vec3& n, Real d, Real h, bool crossed);

// A cloth point (weights w over the particles p: a triangle's barycentrics or an edge's) touching an immovable
// collider point that moves from c0 to c1 over the step; n points from the collider to the cloth's side, d is
// the cloth point's distance along it (Bridson et al. 2002 §7.1 with the collider's inverse mass zero).
void respond_collider_point(const Model& model, const State& out, CollisionScratch& s, const Index* p,
                            const Real* w, int count, const Vec3& c0, const Vec3& c1, const Vec3& n, Real d,
                            Real thick, Real mu, Real h);

// The proximity pass's responses: cloth edge e against cloth edge f (the spring-capped cloth impulse), cloth
// triangle t against collider vertex v (n from the vertex to the triangle's side), cloth edge e against collider
// edge g (px.n towards the cloth edge).
void respond_cloth_edges(const Model& model, const State& out, CollisionScratch& s, Index e, Index f,
                         const EdgeProximity& px, Real d, Real h);
void respond_collider_vertex(const Model& model, const State& out, CollisionScratch& s, Index t, Index v,
                             const TriangleProximity& px, const Vec3& n, Real d, Real h);
void respond_collider_edge(const Model& model, const State& out, CollisionScratch& s, Index e, Index g,
                           const EdgeProximity& px, Real d, Real h);

// The continuous pass's responses (inelastic_separation): cloth triangle t that crossed collider vertex v
// (barycentrics w), and an edge pair that crossed (p the four particles, collider vertices for p[2], p[3] when
// `fixed`; x0, x1 their positions at the start and end of the step).
void respond_collider_vertex_crossing(const Model& model, const State& out, CollisionScratch& s, Index t, Index v,
                                      const Real* w, const Vec3& n, Real d, Real h);
void respond_edge_crossing(const Model& model, const State& out, CollisionScratch& s, const Index* p, bool fixed,
                           const Vec3* x0, const Vec3* x1, const EdgeProximity& px, const Vec3& n, Real d, Real mu,
                           Real h);

}  // namespace clothsim
