#pragma once
// The continuous pass's pairs (Bridson, Fedkiw & Anderson 2002 §6.2): every pair that meets along the step's
// linear trajectories -- coplanar at some time with the vertex within the thickness of the triangle, or the
// edges touching (systems/collision/ccd.h) -- and ends closer than the thickness on the
// side it came from. The continuous pass responds to them; the impact zones (systems/collision/impact_zones.h)
// merge them.
#include <cmath>

#include "systems/collision/ccd.h"
#include "systems/collision/proximity_pairs.h"
#include "systems/collision/response.h"

namespace clothsim {

// Edges whose closest points stay farther apart than this fraction of the thickness where their lines are
// coplanar did not pass through each other during the step: a near miss, left to the proximity passes.
inline constexpr Real near_miss_fraction = 1e-4;

// Edge x[0]x[1] of a cloth against edge x[2]x[3] (another cloth edge, or a collider edge), moving linearly from
// x0 to x1 over the step (Bridson et al. 2002 §4): true when they meet during the step and end closer than the
// thickness along the direction back to the side they came from (crossing_normal, systems/collision/ccd.h); n
// and d are that direction and the end-of-step distance along it. Only a meeting counts, not a pass within the
// thickness: for a near miss the lines' cross product is no direction of approach (on the Rumba an endpoint
// passing a body edge 1.3 mm away was pushed 3 mm sideways every step, whatever the step), and the proximity
// passes already hold the pair the thickness apart.
inline bool edge_edge_crossing(const Vec3 x0[4], const Vec3 x1[4], Real thick, EdgeProximity& px, Vec3& n, Real& d) {
  Real when;
  if (!edge_edge_ccd(x0, x1, near_miss_fraction * thick, when, px)) return false;
  if (!crossing_normal(x0, x1, when, px, n)) return false;
  d = n.dot(((1 - px.s) * x1[0] + px.s * x1[1]) - ((1 - px.t) * x1[2] + px.t * x1[3]));
  return std::isfinite(d) && d < thick;
}

// Every edge pair of for_each_edge_pair that met within the thickness: on_edge(e, f, fixed, px, n, d), e the cloth
// edge and f the other (a collider edge when `fixed`), px.s and px.t where they met, n and d as edge_edge_crossing
// gives them. A cloth edge that came from inside a collider is left to the proximity pass, which sends it out.
// Only pairs whose boxes come within the thickness and whose cloth particles pass keep(particles, count) are
// tested, and only cloth edges whose swept box passes near(box) are walked.
template <class Keep, class Near, class OnEdge>
void for_each_edge_crossing(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                            BroadMode mode, Keep&& keep, Near&& near, OnEdge&& on_edge) {
  const CollisionModel& c = m.collision;
  auto edge_pair = [&](Index e, const Aabb& q, const Index* p, const Vec3* const* px0, const Vec3* const* px1,
                       bool fixed, Index f) {
    const Vec3 x0[4] = {*px0[0], *px0[1], *px0[2], *px0[3]}, x1[4] = {*px1[0], *px1[1], *px1[2], *px1[3]};
    Aabb qi = q;
    qi.lo.array() -= c.max_thickness;
    qi.hi.array() += c.max_thickness;
    Aabb other = swept_box(x0[2], x1[2]);
    grow(other, x0[3]);
    grow(other, x1[3]);
    if (!boxes_overlap(qi, other) || !keep(p, fixed ? 2 : 4)) return;
    EdgeProximity px;
    Vec3 n;
    Real d;
    if (!edge_edge_crossing(x0, x1, edge_pair_reach(m, p, fixed), px, n, d)) return;
    if (d >= edge_pair_thickness(m, p, fixed, px.s, px.t)) return;
    if (fixed) {
      const Vec3 nv = collider_edge_normal(c, s, f);
      if (n.dot(nv) < -0.2 * nv.norm()) return;
    }
    on_edge(e, f, fixed, px, n, d);
  };
  for_each_edge_pair(m, in, out, s, mode, edge_pair, near);
}

// Every crossing of the step: each cloth vertex against the triangles its swept box meets (on_vertex(i, prim,
// corners, w, n, d); for collider meshes only hits from the outside count: they are one-sided), each collider
// vertex against the cloth triangles (on_collider_vertex(t, v, w, n, d), n pointing from the vertex to the side
// the triangle must keep; a hit from the collider's outside, by the vertex's outward direction as in the
// proximity pass), then the edge pairs (for_each_edge_crossing). Only pairs whose cloth particles pass
// keep(particles, count) are tested (the zones' later passes skip pairs none of whose particles they moved), and
// only cloth elements (vertices, edges, triangles against collider vertices) whose swept box passes near(box) are
// walked: near must hold for every element that can have a kept pair.
template <class Keep, class Near, class OnVertex, class OnColliderVertex, class OnEdge>
void for_each_crossing(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                       BroadMode mode, Keep&& keep, Near&& near, OnVertex&& on_vertex,
                       OnColliderVertex&& on_collider_vertex, OnEdge&& on_edge) {
  const CollisionModel& c = m.collision;
  const CandidateLists* lists = usable_candidates(in, s, WalkKind::vertex);
  parallel_over(m.particle_count, contact_grain, [&](Index i) {
    const Real thick = m.particle_thickness[i];
    const Aabb q = vertex_query(in, out, i);
    if (!near(q)) return;
    for_each_candidate_of(m, out, s, mode, lists, i, &i, 1, q, [&](Index slot) {
      const Index prim = c.prim[slot];
      const PrimCorners t = corners(m, in, out, s, prim);
      if (t.cloth && !c.vertex_meets_cloth_triangle(i, t.p)) return;
      if (!t.cloth && m.particle_inv_mass[i] == 0) return;
      const Index cloth_nodes[4] = {i, t.p[0], t.p[1], t.p[2]};
      if (!keep(cloth_nodes, t.cloth ? 4 : 1)) return;
      const Vec3 x0[4] = {in.x[i], t.x0[0], t.x0[1], t.x0[2]}, x1[4] = {out.x[i], t.x1[0], t.x1[1], t.x1[2]};
      Real when;
      TriangleProximity px;
      if (!vertex_triangle_ccd(x0, x1, thick, when, px)) return;
      const Real start = (x0[2] - x0[1]).cross(x0[3] - x0[1]).dot(x0[0] - x0[1]);
      if (!t.cloth && !(start > 0)) return;
      const Vec3 n = (start < 0 ? -1.0 : 1.0) * (x1[2] - x1[1]).cross(x1[3] - x1[1]).normalized();
      const Real d = n.dot(x1[0] - x1[1]);
      if (!std::isfinite(d) || d >= thick) return;
      on_vertex(i, prim, t, px.w, n, d);
    });
  });
  for_each_collider_vertex_pair(m, in, out, s, mode, [&](Index t, Index v) {
    const Index* p = &m.tri_index[3 * t];
    if (!keep(p, 3)) return;
    const Real thick = triangle_thickness(m, p);
    const Vec3 x0[4] = {s.collider_x0[v], in.x[p[0]], in.x[p[1]], in.x[p[2]]};
    const Vec3 x1[4] = {s.collider_x1[v], out.x[p[0]], out.x[p[1]], out.x[p[2]]};
    Real when;
    TriangleProximity px;
    if (!vertex_triangle_ccd(x0, x1, thick, when, px)) return;
    const Vec3 n0 = (x0[2] - x0[1]).cross(x0[3] - x0[1]);
    const Real way = n0.dot(x0[0] - x0[1]) > 0 ? -1 : 1;  // the triangle lay this way from the vertex along n0
    const Vec3 nv = collider_vertex_normal(c, s, v);
    if (way * n0.dot(nv) < -0.2 * n0.norm() * nv.norm()) return;
    const Vec3 n = way * (x1[2] - x1[1]).cross(x1[3] - x1[1]).normalized();
    const Real d = n.dot(x1[1] - x1[0]);
    if (!std::isfinite(d) || d >= thick) return;
    on_collider_vertex(t, v, px.w, n, d);
  }, near);
  for_each_edge_crossing(m, in, out, s, mode, keep, near, on_edge);
}

// The continuous pass, last (Bridson et al. 2002 §6.2): every crossing of for_each_crossing (through the contact
// buffer, systems/collision/contacts.h) is sent back to the side it came from, with the end-of-step distance
// along that direction restored to the thickness by an inelastic impulse and a position-only push spread over the
// cloth particles by their weights. Returns the contacts it responded to. Each pass leaves in s.crossed the cloth
// particles of the pairs it found. With `retest` (every pass after the first) only pairs with such a particle are
// tested: no other pair has moved since the pass before tested it and found it apart; and only elements near
// those particles are walked (systems/collision/reach_grid.h).
std::int64_t collide_continuous(const Model& model, const State& in, State& out, CollisionScratch& s,
                                BroadMode mode, Real h, bool retest);

}  // namespace clothsim
