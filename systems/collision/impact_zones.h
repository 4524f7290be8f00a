#pragma once
// Rigid impact zones, the collision stage's fail-safe (Provot 1997 "Collision and self-collision handling in
// cloth model dedicated to design garments" §4; Bridson, Fedkiw & Anderson 2002 §6.3; Harmon et al. 2008
// "Robust treatment of simultaneous collisions" for why they terminate): the vertices of pairs still crossing
// after the continuous passes are merged into zones (zones that share a vertex merge), and each zone moves as
// one rigid body over the step, keeping its linear and angular momentum. A rigid motion with linear
// trajectories cannot bring four points of one zone into a plane they were not in at the start (below), so
// the crossings left are those between zones, and the zones grow until none is left. A zone that holds
// collider vertices or pins (infinite mass) follows the collider instead, each particle with the body's motion
// next to it (impact_zones.cpp).
//
// The per-zone maths is inline and free of threads, testable alone; the union-find is lock-free with integer
// atomics and links the larger root under the smaller, so a zone's root is its smallest node whatever order the
// threads link in (the zones are the same bytes at any thread count).
#include <atomic>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "core/model.h"
#include "systems/collision/broad_phase.h"

namespace clothsim {

inline constexpr std::uint8_t zone_member = 1;   // the node is in a zone this step
inline constexpr std::uint8_t zone_touched = 2;  // the node is in a pair found by this pass

// The root of node x's zone; halves the path on the way (a benign race: every write points to an ancestor).
inline Index zone_find(ZoneScratch& z, Index x) {
  for (;;) {
    std::atomic_ref<Index> px(z.parent[x]);
    Index p = px.load(std::memory_order_acquire);
    if (p == x) return x;
    const Index g = std::atomic_ref<Index>(z.parent[p]).load(std::memory_order_acquire);
    if (g != p) px.compare_exchange_weak(p, g, std::memory_order_acq_rel);
    x = g;
  }
}

// Merges the zones of a and b; true when they were apart. The larger root is linked under the smaller with a
// compare-and-swap that fails, and retries, when another thread linked that root first.
inline bool zone_unite(ZoneScratch& z, Index a, Index b) {
  for (;;) {
    a = zone_find(z, a);
    b = zone_find(z, b);
    if (a == b) return false;
    if (a > b) std::swap(a, b);
    Index expected = b;
    if (std::atomic_ref<Index>(z.parent[b]).compare_exchange_strong(expected, a, std::memory_order_acq_rel))
      return true;
  }
}

// A pair still crossing: its nodes join one zone and are marked for this pass's refit. Returns the number of
// zones it merged (0 when all its nodes already shared one).
inline int add_zone_pair(ZoneScratch& z, const Index* nodes, int count) {
  int links = 0;
  for (int k = 0; k < count; ++k) {
    std::atomic_ref<std::uint8_t>(z.flag[nodes[k]]).fetch_or(zone_member | zone_touched, std::memory_order_relaxed);
    if (k > 0) links += zone_unite(z, nodes[0], nodes[k]);
  }
  return links;
}

// A rigid velocity field u(x) = velocity + omega x (x - center) fitted to weighted samples (w_k, x_k, u_k) by
// least squares: center and velocity are the weighted means, and omega solves I omega = L with
// I = sum w (|r|^2 1 - r r^T) and L = sum w r x (u - velocity), r = x - center. With w the masses, these are the
// samples' centre of mass, linear momentum / M and angular momentum about the centre (Bridson et al. 2002 §6.3).
// A singular I (collinear samples: no rotation about their line is defined) is inverted on its range only.
struct RigidFit {
  Vec3 center = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  Vec3 omega = Vec3::Zero();
  Vec3 momentum = Vec3::Zero();  // L about the center, before inverting I
  Real weight = 0;
};

// omega = I^+ L, the pseudo-inverse dropping eigenvalues below 1e-12 of the largest.
inline Vec3 solve_inertia(const Mat3& inertia, const Vec3& l) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(inertia);
  const Vec3 lambda = eig.eigenvalues();
  const Real cut = 1e-12 * std::max(lambda.cwiseAbs().maxCoeff(), Real(0));
  Vec3 y = eig.eigenvectors().transpose() * l;
  for (int k = 0; k < 3; ++k) y[k] = lambda[k] > cut ? y[k] / lambda[k] : 0;
  return eig.eigenvectors() * y;
}

// Inertia tensor sum w (|r|^2 1 - r r^T) of weighted points about c, in sample order.
template <class Sample>
Mat3 inertia_about(int count, const Vec3& c, Sample&& sample) {
  Mat3 inertia = Mat3::Zero();
  for (int k = 0; k < count; ++k) {
    Real w;
    Vec3 x, u;
    sample(k, w, x, u);
    if (w == 0) continue;
    const Vec3 r = x - c;
    inertia += w * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  return inertia;
}

// sample(k, w, x, u) gives the k-th sample; sums run in sample order (fixed order: the same bytes every run).
template <class Sample>
RigidFit fit_rigid_motion(int count, Sample&& sample) {
  RigidFit f;
  Vec3 wx = Vec3::Zero(), wu = Vec3::Zero();
  for (int k = 0; k < count; ++k) {
    Real w;
    Vec3 x, u;
    sample(k, w, x, u);
    f.weight += w;
    wx += w * x;
    wu += w * u;
  }
  if (!(f.weight > 0)) return f;
  f.center = wx / f.weight;
  f.velocity = wu / f.weight;
  for (int k = 0; k < count; ++k) {
    Real w;
    Vec3 x, u;
    sample(k, w, x, u);
    if (w != 0) f.momentum += w * (x - f.center).cross(u - f.velocity);
  }
  f.omega = solve_inertia(inertia_about(count, f.center, sample), f.momentum);
  return f;
}

// The rotation by angle |a| about a / |a| (the identity for a = 0).
inline Mat3 rotation_of(const Vec3& a) {
  const Real angle = a.norm();
  if (!(angle > 0)) return Mat3::Identity();
  return Eigen::AngleAxis<Real>(angle, a / angle).toRotationMatrix();
}

// Why a rigid zone cannot cross itself: its points move linearly from x0 to x1 = c + R (x0 - c0) (+ a shared
// translation), so any difference of two of them at time t is M(t) d0 with M(t) = (1 - t) 1 + t R. For a
// rotation by less than pi, det M(t) > 0 on [0, 1] (on the rotation plane M scales by |1 - t + t e^{i angle}|
// > 0), so det[d1 d2 d3] -- four points' coplanarity -- keeps its sign: no vertex-triangle or edge-edge pair of
// the zone becomes coplanar in the step unless it started so.

// Every node on its own, no zone (at the start of a step's zone passes).
void reset_zones(ZoneScratch& z);
// After a pass has added its pairs: the zones holding a node of those pairs, numbered by root, members in CSR.
void gather_zones(ZoneScratch& z);
// Moves the gathered zones as rigid bodies over the step (out.x and out.v of their cloth particles).
void rigidify_zones(const Model& model, const State& in, State& out, const CollisionScratch& s, Real h);
// Boxes round the zones' cloth members (z.reach_box, one per root, from z.flag and z.parent), for the later passes'
// walks: every cloth element that can have a pair with a zone member overlaps one of them, so an element whose
// swept box overlaps none is skipped before its broad-phase query. Reads the cloth's prim boxes (s.prim_box).
void gather_reach_boxes(const Model& model, const State& in, const State& out, const CollisionScratch& s,
                        ZoneScratch& z);
// Whether box q overlaps one of the reach boxes gather_reach_boxes made.
bool near_a_zone(const ZoneScratch& z, const Aabb& q);
// Adds the step's zones and their sizes to `figures`.
void count_zones(ZoneScratch& z, ZoneFigures& figures);

// The zone driver, after continuous passes that left crossings: each pass finds the pairs the continuous pass
// would still respond to (for_each_crossing, systems/collision/continuous_pairs.h), merges their nodes into zones
// and moves the zones that grew, until a pass finds none (impact_zones.cpp). The first pass reads the last
// continuous pass's s.crossed: only pairs with one of its particles can be found. Returns what the zones did.
ZoneFigures resolve_impact_zones(const Model& model, const State& in, State& out, CollisionScratch& s,
                                 BroadMode mode, Real h);

}  // namespace clothsim
