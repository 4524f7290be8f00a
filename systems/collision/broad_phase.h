#pragma once
// The collide stage's broad phase: swept, thickness-inflated boxes of every prim (cloth triangles, then collider
// mesh triangles), one spatial hash or BVH over them per pass, and the candidate walks the proximity and continuous
// passes share (Bridson, Fedkiw & Anderson 2002 §6: every pair whose swept boxes meet is tested). The walks are
// templates so that each pass's per-pair test inlines into the loop over candidates.
#include "core/model.h"
#include "systems/collision/bvh.h"
#include "systems/collision/spatial_hash.h"
#include "systems/parallel.h"

namespace clothsim {

// Which broad phase a walk queries: the scene's hash or BVH, or every prim (the tests' reference).
enum class BroadMode { hash, bvh, brute };

// Swept, thickness-inflated prim boxes and the query bounds, then the scene's broad phase.
void build_broad_phase(const Model& model, const State& in, const State& out, CollisionScratch& s);

// Cloth vertices, triangles or edges a task of the contact passes takes: each costs a broad-phase query.
inline constexpr Index contact_grain = 256;

inline Aabb swept_box(const Vec3& a0, const Vec3& a1) { return {a0.cwiseMin(a1), a0.cwiseMax(a1)}; }
inline void grow(Aabb& b, const Vec3& p) { b.lo = b.lo.cwiseMin(p); b.hi = b.hi.cwiseMax(p); }

// Calls visit(slot) for every prim slot whose box overlaps q.
template <class Visit>
void for_each_candidate(const Model& m, const CollisionScratch& s, BroadMode mode, const Aabb& q, Visit&& visit) {
  switch (mode) {
    case BroadMode::hash: query_spatial_hash(s, q, visit); break;
    case BroadMode::bvh: query_bvh(m.collision, s, q, visit); break;
    case BroadMode::brute:
      for (Index slot = 0; slot < Index(m.collision.prim.size()); ++slot)
        if (boxes_overlap(q, s.prim_box[slot])) visit(slot);
      break;
  }
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

// Every collider-mesh vertex whose swept box may come within the thickness of cloth triangle t's swept box,
// through the broad phase's collider triangles: a vertex is reported only by its lowest triangle, so each
// (t, vertex) pair once. on_pair(t, vertex). Nothing for a scene without collider meshes.
template <class OnPair>
void for_each_collider_vertex_pair(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                                   BroadMode mode, OnPair&& on_pair) {
  const CollisionModel& c = m.collision;
  if (c.mesh_vertex_first_tri.empty()) return;
  parallel_over(m.tri_count, contact_grain, [&](Index t) {
    const Index* p = &m.tri_index[3 * t];
    if (m.particle_inv_mass[p[0]] == 0 && m.particle_inv_mass[p[1]] == 0 && m.particle_inv_mass[p[2]] == 0) return;
    Aabb q = swept_box(in.x[p[0]], out.x[p[0]]);
    for (int k = 1; k < 3; ++k) { grow(q, in.x[p[k]]); grow(q, out.x[p[k]]); }
    for_each_candidate(m, s, mode, q, [&](Index slot) {
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

}  // namespace clothsim
