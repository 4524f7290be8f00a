#pragma once
// The proximity pass's pairs (Bridson, Fedkiw & Anderson 2002 §6.1, §7.1): every pair within the thickness at the
// end of the step, of four kinds: a cloth vertex against a triangle (cloth or collider mesh), two cloth edges, a
// cloth triangle against a collider vertex, and a cloth edge against a collider edge. The side a pair must keep is
// the one it came from (one-sided for collider meshes: their normals point out).
#include "systems/collision/broad_phase.h"
#include "systems/collision/colliders.h"
#include "systems/collision/proximity.h"
#include "systems/collision/response.h"

namespace clothsim {

// The thickness of a cloth triangle's contacts: the largest of its corners'.
inline Real triangle_thickness(const Model& m, const Index* p) {
  return std::max({m.particle_thickness[p[0]], m.particle_thickness[p[1]], m.particle_thickness[p[2]]});
}

// Edge-edge contacts: each cloth edge's thickness interpolated between its ends at the closest point (s on
// p[0]p[1], t on p[2]p[3]; a collider edge, `fixed`, has none), the larger of the two sides, so the contact
// does not depend on which edge is numbered first. edge_pair_reach bounds it for the detection tests.
inline Real edge_pair_reach(const Model& m, const Index* p, bool fixed) {
  const Real own = std::max(m.particle_thickness[p[0]], m.particle_thickness[p[1]]);
  return fixed ? own : std::max({own, m.particle_thickness[p[2]], m.particle_thickness[p[3]]});
}
inline Real edge_thickness_at(const Model& m, Index a, Index b, Real s) {
  const Real ha = m.particle_thickness[a];
  return ha + s * (m.particle_thickness[b] - ha);  // exactly ha when both ends agree
}
inline Real edge_pair_thickness(const Model& m, const Index* p, bool fixed, Real s, Real t) {
  const Real own = edge_thickness_at(m, p[0], p[1], s);
  return fixed ? own : std::max(own, edge_thickness_at(m, p[2], p[3], t));
}

// Which way along the cloth triangle's unit normal nt the triangle must lie from a collider vertex: the
// collider's outside, by the vertex's outward direction nv, where that decides (|cos| > 0.2), so that a triangle
// already pushed past the vertex is sent back out; otherwise (a triangle edge-on to the surface) the side it lay
// on at the start of the step, from start = nt0 . (vertex - corner) at the start (the vertex's side of the
// triangle).
inline Real collider_vertex_side(const Vec3& nt, const Vec3& nv, Real start) {
  const Real cos = nt.dot(nv);
  if (std::abs(cos) > 0.2 * nv.norm()) return cos > 0 ? 1 : -1;
  return start > 0 ? -1 : 1;
}

// The side a cloth edge near collider edge g must keep, as for a cloth triangle near a collider vertex
// (collider_vertex_side): the collider's outside, by the edge's outward direction nv, where that decides
// (|cos| > 0.2), so that a cloth edge already through a body edge is sent back out; otherwise the side it came
// from, as edge_pair_proximity left it. px.n (from the collider edge to the cloth edge) and the signed distance
// d are turned to that side.
inline void collider_edge_side(const Vec3& nv, EdgeProximity& px, Real& d) {
  const Vec3 towards = d < 0 ? Vec3(-px.n) : px.n;  // where the cloth edge lies from the collider's at the end
  const Real cos = towards.dot(nv);
  if (std::abs(cos) <= 0.2 * nv.norm()) return;
  const Real distance = std::abs(d);
  px.n = cos > 0 ? towards : Vec3(-towards);
  d = cos > 0 ? distance : -distance;
}

// Edge x[0]x[1] against edge x[2]x[3] at the end of the step (x1; x0 at its start; pointers, so a pair the
// boxes reject reads no start position): the closest points within the thickness h, pointed back to the side the
// first edge came from when the pair crossed during the step. False when apart.
inline bool edge_pair_proximity(const Vec3* const x0[4], const Vec3* const x1[4], Real h, EdgeProximity& px,
                                Real& d) {
  // Cheap reject before the closest points: the end-of-step boxes must come within h.
  const Aabb ea = swept_box(*x1[0], *x1[1]), eb = swept_box(*x1[2], *x1[3]);
  if (((ea.lo.array() - h) > eb.hi.array()).any() || ((eb.lo.array() - h) > ea.hi.array()).any()) return false;
  if (!edge_edge_proximity(*x1[0], *x1[1], *x1[2], *x1[3], px) || px.d >= h) return false;
  EdgeProximity start;
  d = px.d;
  if (edge_edge_proximity(*x0[0], *x0[1], *x0[2], *x0[3], start) && start.n.dot(px.n) < 0) {
    px.n = start.n;  // crossed during the step: push back to the side it came from
    d = -px.d;
  }
  return true;
}

// Vertex-triangle and edge-edge proximities of the configuration out (sides taken from in), through one broad
// phase. on_vertex(i, prim, corners, proximity, d) gets d signed: negative when i crossed to the wrong side;
// on_edge(e, f, proximity, d) likewise. Against collider meshes also: on_collider_vertex(t, v, proximity, n, d),
// collider vertex v within the thickness of cloth triangle t, n the unit direction from the vertex to the side
// the triangle must keep, d the triangle's signed distance along it; on_collider_edge(e, g, proximity, d),
// cloth edge e against collider edge g, px.n pointing to the cloth edge's side.
template <class OnVertex, class OnEdge, class OnColliderVertex, class OnColliderEdge>
void for_each_proximity(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                        BroadMode mode, OnVertex&& on_vertex, OnEdge&& on_edge, OnColliderVertex&& on_collider_vertex,
                        OnColliderEdge&& on_collider_edge) {
  const CollisionModel& c = m.collision;
  if (c.prim.empty()) return;
  const CandidateLists* lists = usable_candidates(in, s, WalkKind::vertex);
  parallel_over(m.particle_count, contact_grain, [&](Index i) {
    const Real thickness = m.particle_thickness[i], hold_reach = collider_reach(s, thickness);
    const Aabb q = vertex_query(in, out, i);
    const Real own_motion = (out.x[i] - in.x[i]).norm();
    for_each_candidate_of(m, out, s, mode, lists, i, &i, 1, q, [&](Index slot) {
      const Index prim = c.prim[slot];
      const PrimCorners t = corners(m, in, out, s, prim);
      if (t.cloth && !c.vertex_meets_cloth_triangle(i, t.p)) return;
      const Real h = t.cloth ? thickness : hold_reach;  // a collider's pairs reach further for the contact filter
      const Vec3& p = out.x[i];
      const Vec3 tlo = t.x1[0].cwiseMin(t.x1[1]).cwiseMin(t.x1[2]), thi = t.x1[0].cwiseMax(t.x1[1]).cwiseMax(t.x1[2]);
      if (((p.array() + h + own_motion) < tlo.array()).any() || ((p.array() - h - own_motion) > thi.array()).any())
        return;
      TriangleProximity px;
      if (!vertex_triangle_proximity(out.x[i], t.x1[0], t.x1[1], t.x1[2], h, px)) return;
      // The side is the one at the start of the step (one-sided for collider meshes: their normals point out).
      Real side = 1;
      if (t.cloth) side = (t.x0[1] - t.x0[0]).cross(t.x0[2] - t.x0[0]).dot(in.x[i] - t.x0[0]) < 0 ? -1 : 1;
      const Real d = side * px.d;
      Real motion = own_motion;
      for (int k = 0; k < 3; ++k) motion = std::max(motion, own_motion + (t.x1[k] - t.x0[k]).norm());
      if (d >= h || d <= -(h + motion)) return;
      px.n *= side;
      on_vertex(i, prim, t, px, d);
    });
  });
  for_each_collider_vertex_pair(m, in, out, s, mode, [&](Index t, Index v) {
    const Index* p = &m.tri_index[3 * t];
    const Real h = triangle_thickness(m, p);
    const Vec3 &v0 = s.collider_x0[v], &v1 = s.collider_x1[v];
    TriangleProximity px;
    if (!vertex_triangle_proximity(v1, out.x[p[0]], out.x[p[1]], out.x[p[2]], h, px)) return;
    Real motion = (v1 - v0).norm(), own = 0;
    for (int k = 0; k < 3; ++k) own = std::max(own, (out.x[p[k]] - in.x[p[k]]).norm());
    motion += own;
    if (!(std::abs(px.d) < h + motion)) return;
    const Real start = (in.x[p[1]] - in.x[p[0]]).cross(in.x[p[2]] - in.x[p[0]]).dot(v0 - in.x[p[0]]);
    const Real side = collider_vertex_side(px.n, collider_vertex_normal(c, s, v), start);
    const Real d = -side * px.d;  // px.d: the vertex's height over the triangle along px.n
    if (d >= h || d <= -(h + motion)) return;
    on_collider_vertex(t, v, px, Vec3(side * px.n), d);
  });
  auto edge_pair = [&](Index e, const Aabb&, const Index* p, const Vec3* const* x0, const Vec3* const* x1, bool fixed,
                       Index f) {
    EdgeProximity px;
    Real d;
    if (!edge_pair_proximity(x0, x1, edge_pair_reach(m, p, fixed), px, d)) return;
    if (px.d >= edge_pair_thickness(m, p, fixed, px.s, px.t)) return;
    if (fixed) {
      collider_edge_side(collider_edge_normal(c, s, f), px, d);
      on_collider_edge(e, f, px, d);
    } else {
      on_edge(e, f, px, d);
    }
  };
  for_each_edge_pair(m, in, out, s, mode, edge_pair);
}

// The collide stage's proximity pass (Bridson et al. 2002 §7): every pair for_each_proximity finds goes into the
// contact buffer (systems/collision/contacts.h), and each gets its response (systems/collision/response.h) added
// to the accumulators of s.
void respond_proximities(const Model& model, const State& in, const State& out, CollisionScratch& s, BroadMode mode,
                         Real h);

}  // namespace clothsim
