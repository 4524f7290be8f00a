#pragma once
// The collide stage's broad phase: swept, thickness-inflated boxes of every prim (cloth triangles, then collider
// mesh triangles); over the cloth's, the scene's spatial hash or BVH, rebuilt every pass; over the colliders',
// their own BVH, refitted once a step (collider vertices do not move between passes); and the candidate walks the
// proximity and continuous passes share (Bridson, Fedkiw & Anderson 2002 §6: every pair whose swept boxes meet is
// tested). The walks are templates so that each pass's per-pair test inlines into the loop over candidates.
#include "core/model.h"
#include "systems/collision/bvh.h"
#include "systems/collision/candidate_cache.h"
#include "systems/collision/spatial_hash.h"
#include "systems/parallel.h"

namespace clothsim {

// Which broad phase a walk queries: the scene's hash or BVH and the colliders' tree, or every prim (the tests'
// reference); hash_cloth and bvh_cloth query the cloth's side alone, for walks that want cloth-cloth pairs only.
enum class BroadMode { hash, bvh, brute, hash_cloth, bvh_cloth };

// The walk the scene's broad phase setting asks for.
inline BroadMode broad_mode(const CollisionModel& c) {
  return c.broad_phase == BroadPhase::bvh ? BroadMode::bvh : BroadMode::hash;
}
// The same broad phase without the colliders' side: the walks then find no pair with a collider.
inline BroadMode cloth_side(BroadMode mode) {
  return mode == BroadMode::bvh ? BroadMode::bvh_cloth : mode == BroadMode::hash ? BroadMode::hash_cloth : mode;
}
inline bool walks_colliders(BroadMode mode) { return mode != BroadMode::hash_cloth && mode != BroadMode::bvh_cloth; }

// Both sides for the step's collider positions (s.collider_x0, collider_x1) and the cloth's in and out.
void build_broad_phase(const Model& model, const State& in, const State& out, CollisionScratch& s);
// The cloth's side alone, after a pass has moved the cloth: swept, thickness-inflated cloth prim boxes, the query
// bounds, then the scene's hash or the cloth tree.
void build_cloth_broad_phase(const Model& model, const State& in, const State& out, CollisionScratch& s);

// Cloth vertices, triangles or edges a task of the contact passes takes: each costs a broad-phase query.
inline constexpr Index contact_grain = 256;

// A walk's filter on each cloth element's swept box before its broad-phase query: false skips the element (the
// impact zones' later passes visit only elements near a zone). Everywhere keeps them all.
struct Everywhere {
  bool operator()(const Aabb&) const { return true; }
};

inline Aabb swept_box(const Vec3& a0, const Vec3& a1) { return {a0.cwiseMin(a1), a0.cwiseMax(a1)}; }
inline void grow(Aabb& b, const Vec3& p) { b.lo = b.lo.cwiseMin(p); b.hi = b.hi.cwiseMax(p); }

// Calls visit(slot) for every prim slot whose box overlaps q: the cloth's, then the colliders'.
template <class Visit>
void for_each_candidate(const Model& m, const CollisionScratch& s, BroadMode mode, const Aabb& q, Visit&& visit) {
  const CollisionModel& c = m.collision;
  switch (mode) {
    case BroadMode::hash:
    case BroadMode::hash_cloth: query_spatial_hash(s, q, visit); break;
    case BroadMode::bvh:
    case BroadMode::bvh_cloth: query_bvh(c.cloth_tree, s.cloth_node_box, q, visit); break;
    case BroadMode::brute:
      for (Index slot = 0; slot < Index(c.prim.size()); ++slot)
        if (boxes_overlap(q, s.prim_box[slot])) visit(slot);
      return;
  }
  if (walks_colliders(mode)) query_bvh(c.collider_tree, s.collider_node_box, q, visit);
}

// The query boxes of the walks' cloth elements: their swept boxes over the step.
inline Aabb vertex_query(const State& in, const State& out, Index i) { return swept_box(in.x[i], out.x[i]); }
inline Aabb edge_query(const CollisionModel& c, const State& in, const State& out, Index e) {
  const Index a = c.edge_a[e], b = c.edge_b[e];
  Aabb q = swept_box(in.x[a], out.x[a]);
  grow(q, in.x[b]);
  grow(q, out.x[b]);
  return q;
}
inline Aabb triangle_query(const Model& m, const State& in, const State& out, Index t) {
  const Index* p = &m.tri_index[3 * t];
  Aabb q = swept_box(in.x[p[0]], out.x[p[0]]);
  for (int k = 1; k < 3; ++k) { grow(q, in.x[p[k]]); grow(q, out.x[p[k]]); }
  return q;
}

// for_each_candidate for the cloth element `element` of particles p[0, n), through its candidate list when
// `lists` (usable_candidates) holds one and the particles are near where it was made: the listed slots whose boxes
// overlap q, runaways apart (systems/collision/candidate_cache.h). The same slots as the walk, in another order.
template <class Visit>
void for_each_candidate_of(const Model& m, const State& out, const CollisionScratch& s, BroadMode mode,
                           const CandidateLists* lists, Index element, const Index* p, int n, const Aabb& q,
                           Visit&& visit) {
  const CandidateCache& k = s.candidates;
  if (!lists || (mode != BroadMode::bvh && mode != BroadMode::bvh_cloth) || !near_lists(k, out, p, n)) {
    for_each_candidate(m, s, mode, q, visit);
    return;
  }
  const Index* listed = lists->block[std::size_t(element / candidate_block)].data();
  const Index end = lists->end[std::size_t(element)];
  const Index slots = walks_colliders(mode) ? Index(m.collision.prim.size()) : m.collision.cloth_prim_count;
  const Index cloth_slots = m.collision.cloth_prim_count;
  for (Index j = element % candidate_block == 0 ? 0 : lists->end[std::size_t(element) - 1]; j < end; ++j) {
    const Index slot = listed[j];
    if (slot >= slots) break;  // the colliders' slots come last
    if (slot < cloth_slots && k.is_runaway[std::size_t(slot)]) continue;
    if (boxes_overlap(q, s.prim_box[slot])) visit(slot);
  }
  for (const Index slot : k.runaway)
    if (boxes_overlap(q, s.prim_box[slot])) visit(slot);
}

// Corners of a broad-phase prim at the start and end of the step.
struct PrimCorners {
  Index p[3];
  Vec3 x0[3], x1[3];
  bool cloth;
};
inline PrimCorners corners(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                           Index prim) {
  PrimCorners c;
  c.cloth = prim < m.tri_count;
  for (int k = 0; k < 3; ++k) {
    if (c.cloth) {
      c.p[k] = m.tri_index[3 * prim + k];
      c.x0[k] = in.x[c.p[k]];
      c.x1[k] = out.x[c.p[k]];
    } else {
      c.p[k] = m.collision.mesh_tri_index[3 * (prim - m.tri_count) + k];
      c.x0[k] = s.collider_x0[c.p[k]];
      c.x1[k] = s.collider_x1[c.p[k]];
    }
  }
  return c;
}

// The velocity over the step of h of the point with weights w (three) on the prim.
inline Vec3 prim_velocity(const PrimCorners& t, const Real* w, Real h) {
  Vec3 v = Vec3::Zero();
  for (int k = 0; k < 3; ++k) v += w[k] * (t.x1[k] - t.x0[k]) / h;
  return v;
}

// Every collider-mesh vertex whose swept box may come within the thickness of cloth triangle t's swept box,
// through the broad phase's collider triangles: a vertex is reported only by its lowest triangle, so each
// (t, vertex) pair once. on_pair(t, vertex). Nothing for a scene without collider meshes. Triangles whose swept
// box fails near(box) are skipped.
template <class OnPair, class Near = Everywhere>
void for_each_collider_vertex_pair(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                                   BroadMode mode, OnPair&& on_pair, Near&& near = Near{}) {
  const CollisionModel& c = m.collision;
  if (c.mesh_vertex_first_tri.empty() || !walks_colliders(mode)) return;
  const CandidateLists* lists = usable_candidates(in, s, WalkKind::triangle);
  parallel_over(m.tri_count, contact_grain, [&](Index t) {
    const Index* p = &m.tri_index[3 * t];
    if (m.particle_inv_mass[p[0]] == 0 && m.particle_inv_mass[p[1]] == 0 && m.particle_inv_mass[p[2]] == 0) return;
    const Aabb q = triangle_query(m, in, out, t);
    if (!near(q)) return;
    for_each_candidate_of(m, out, s, mode, lists, t, p, 3, q, [&](Index slot) {
      const Index prim = c.prim[slot];
      if (prim < m.tri_count) return;
      const Index tri = prim - m.tri_count;
      for (int k = 0; k < 3; ++k) {
        const Index v = c.mesh_tri_index[3 * tri + k];
        if (c.mesh_vertex_first_tri[v] == tri) on_pair(t, v);
      }
    });
  });
}

// Whether cloth edge e is tested against cloth edge f of cloth prim `prim`: each pair once, from the lower edge id
// and through f's first triangle; neither adjacent edges nor edges of cloths that do not collide.
inline bool cloth_edge_pair(const CollisionModel& c, Index e, Index f, Index prim) {
  if (f <= e || c.edge_first_tri[f] != prim) return false;
  const Index a = c.edge_a[e], b = c.edge_b[e], fa = c.edge_a[f], fb = c.edge_b[f];
  return !c.edges_adjacent(a, b, fa, fb) && c.cloths_collide(c.particle_cloth[a], c.particle_cloth[fa]);
}

// visit(f) for each edge f of cloth prim `prim` that cloth edge e is tested against (cloth_edge_pair); none when
// e's cloth collides with no cloth. The edge walk and its candidate lists (candidate_cache.cpp) both use it.
template <class Visit>
void for_each_paired_edge(const CollisionModel& c, Index e, Index prim, Visit&& visit) {
  if (!c.edge_contact[e]) return;
  for (int k = 0; k < 3; ++k) {
    const Index f = c.tri_edge[3 * prim + k];
    if (cloth_edge_pair(c, e, f, prim)) visit(f);
  }
}

// Every cloth edge e against the edges of the prims its swept box q meets, the one edge-edge walk of the proximity
// and continuous passes: self-colliding cloths' edges against each other (each pair once, from the lower edge id;
// neither adjacent edges nor edges of cloths that do not collide), and every cloth edge against collider-mesh edges
// (each reported by its lowest triangle). on_pair(e, q, p, x0, x1, fixed, f) with q the cloth edge's swept box,
// p the four particles (collider vertices for p[2], p[3] when `fixed`), x0 and x1 pointers to their positions at
// the start and end of the step, and f the other edge (a cloth edge, or a collider edge when fixed). Cloth edges
// whose swept box fails near(q) are skipped.
template <class OnPair, class Near = Everywhere>
void for_each_edge_pair(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                        BroadMode mode, OnPair&& on_pair, Near&& near = Near{}) {
  const CollisionModel& c = m.collision;
  const bool meshes = !c.mesh_edge_a.empty() && walks_colliders(mode);
  if (!c.cloth_contact && !meshes) return;
  const CandidateLists* lists = usable_candidates(in, s, WalkKind::edge);
  parallel_over(Index(c.edge_a.size()), contact_grain, [&](Index e) {
    if (!meshes && !c.edge_contact[e]) return;
    const Index a = c.edge_a[e], b = c.edge_b[e];
    const Aabb q = edge_query(c, in, out, e);
    if (!near(q)) return;
    const Index ends[2] = {a, b};
    for_each_candidate_of(m, out, s, mode, lists, e, ends, 2, q, [&](Index slot) {
      const Index prim = c.prim[slot];
      if (prim >= m.tri_count) {
        const Index tri = prim - m.tri_count;
        for (int k = 0; k < 3; ++k) {
          const Index g = c.mesh_tri_edge[3 * tri + k];
          if (c.mesh_edge_first_tri[g] != tri) continue;
          const Index ga = c.mesh_edge_a[g], gb = c.mesh_edge_b[g];
          const Vec3* const x0[4] = {&in.x[a], &in.x[b], &s.collider_x0[ga], &s.collider_x0[gb]};
          const Vec3* const x1[4] = {&out.x[a], &out.x[b], &s.collider_x1[ga], &s.collider_x1[gb]};
          const Index p[4] = {a, b, ga, gb};
          on_pair(e, q, p, x0, x1, true, g);
        }
        return;
      }
      for_each_paired_edge(c, e, prim, [&](Index f) {
        const Index fa = c.edge_a[f], fb = c.edge_b[f];
        const Vec3* const x0[4] = {&in.x[a], &in.x[b], &in.x[fa], &in.x[fb]};
        const Vec3* const x1[4] = {&out.x[a], &out.x[b], &out.x[fa], &out.x[fb]};
        const Index p[4] = {a, b, fa, fb};
        on_pair(e, q, p, x0, x1, false, f);
      });
    });
  });
}

}  // namespace clothsim
