#pragma once
// The collider's side of the collide stage: where the collider meshes are over the step, which way their
// surfaces face at a vertex or an edge (meshes are one-sided: their normals point out), and the analytic
// colliders (spheres, planes), whose exact signed distances need no broad phase.
#include "core/model.h"

namespace clothsim {

// Collider mesh vertices at the start and end of the step that begins at `time` (s since the start frame) and
// lasts h (animated colliders interpolated linearly between their frames, read from s.collider_frames, which
// must hold them: sim/collider_track.h; static ones stay).
void place_colliders(const Model& model, Real time, Real h, CollisionScratch& s);

// Spheres and planes against every cloth particle: the collider response (Bridson, Fedkiw & Anderson 2002 §7.2)
// added to the accumulators of s.
void collide_analytic(const Model& model, State& out, CollisionScratch& s, Real h);

// Outward direction at collider vertex v at the end of the step: the sum of its triangles' normals (area
// weighted, not normalised), gathered in triangle order.
inline Vec3 collider_vertex_normal(const CollisionModel& c, const CollisionScratch& s, Index v) {
  Vec3 n = Vec3::Zero();
  for (Index k = c.mesh_vertex_tri_offset[v]; k < c.mesh_vertex_tri_offset[v + 1]; ++k) {
    const Index* t = &c.mesh_tri_index[3 * c.mesh_vertex_tri[k]];
    n += (s.collider_x1[t[1]] - s.collider_x1[t[0]]).cross(s.collider_x1[t[2]] - s.collider_x1[t[0]]);
  }
  return n;
}

// Outward direction at collider edge g at the end of the step: the sum of its end vertices' outward directions
// (not normalised).
inline Vec3 collider_edge_normal(const CollisionModel& c, const CollisionScratch& s, Index g) {
  return collider_vertex_normal(c, s, c.mesh_edge_a[g]) + collider_vertex_normal(c, s, c.mesh_edge_b[g]);
}

}  // namespace clothsim
