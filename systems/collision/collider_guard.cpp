#include "systems/collision/collider_guard.h"

#include <limits>

#include "systems/collision/broad_phase.h"
#include "systems/collision/colliders.h"
#include "systems/collision/response.h"
#include "systems/reduce.h"

namespace clothsim {

namespace {

// Barycentric weights of point q of triangle (a, b, c), by the sub-triangles' areas along the normal.
Vec3 barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q) {
  const Vec3 face = (b - a).cross(c - a);
  const Real area2 = face.squaredNorm();
  if (!(area2 > 0)) return Vec3(1, 0, 0);
  return Vec3((b - q).cross(c - q).dot(face), (c - q).cross(a - q).dot(face), (a - q).cross(b - q).dot(face)) / area2;
}

}  // namespace

bool behind_collider_triangle(const Model& m, const CollisionScratch& s, Index tri, const Vec3& x, const Vec3& q) {
  const CollisionModel& c = m.collision;
  const Index* v = &c.mesh_tri_index[3 * tri];
  const Vec3 &a = s.collider_x1[v[0]], &b = s.collider_x1[v[1]], &cc = s.collider_x1[v[2]];
  const Vec3 face = (b - a).cross(cc - a);
  if (!(face.squaredNorm() > 0)) return false;
  // Which corners q lies on: all three weights positive is the face, one zero an edge, two a corner.
  const Vec3 w = barycentric(a, b, cc, q);
  const Real tiny = 1e-9;
  Vec3 normal = Vec3::Zero();
  int corners = 0;
  for (int k = 0; k < 3; ++k)
    if (w[k] > tiny) {
      normal += collider_vertex_normal(c, s, v[k]);
      ++corners;
    }
  if (corners == 3 || corners == 0) normal = face;
  return (x - q).dot(normal) < 0;
}

Index guard_collider_surfaces(const Model& m, State& out, const CollisionScratch& s, Real h) {
  const CollisionModel& c = m.collision;
  if (c.mesh_tri_collider.empty() || s.collider_node_box.empty()) return 0;
  return deterministic_sum(m.particle_count, particle_grain, Index(0), [&](Index i) -> Index {
    if (m.particle_inv_mass[i] == 0) return 0;
    const Vec3 x = out.x[i];
    const Real reach = collider_guard_reach * m.particle_thickness[i];
    const Aabb box{Vec3(x.array() - reach), Vec3(x.array() + reach)};
    Real best = reach * reach;
    Index nearest = -1;
    Vec3 on = x;
    query_bvh(c.collider_tree, s.collider_node_box, box, [&](Index slot) {
      const Index tri = c.prim[slot] - m.tri_count;
      const Index* v = &c.mesh_tri_index[3 * tri];
      const Vec3 q = closest_point_on_triangle(x, s.collider_x1[v[0]], s.collider_x1[v[1]], s.collider_x1[v[2]]);
      const Real d2 = (x - q).squaredNorm();
      // Ties go to the lower triangle, so the visiting order does not matter.
      if (d2 < best || (d2 == best && nearest >= 0 && tri < nearest)) {
        best = d2;
        nearest = tri;
        on = q;
      }
    });
    if (nearest < 0 || !(best > 0) || !behind_collider_triangle(m, s, nearest, x, on)) return 0;
    const Vec3 u = (on - x) / std::sqrt(best);  // outwards
    out.x[i] = on + collider_guard_margin * m.particle_thickness[i] * u;
    const Real vn = out.v[i].dot(u);
    if (vn < 0) out.v[i] -= vn * u;
    // Held there from now on: by the strain limit's planes in this step, by the next solve's filter after it.
    if (out.contact.empty()) return 1;
    const Index* v = &c.mesh_tri_index[3 * nearest];
    const Vec3 w = barycentric(s.collider_x1[v[0]], s.collider_x1[v[1]], s.collider_x1[v[2]], on);
    Vec3 moving = Vec3::Zero();
    for (int k = 0; k < 3; ++k) moving += w[k] * (s.collider_x1[v[k]] - s.collider_x0[v[k]]) / h;
    out.contact[i] = {u, moving, collider_friction(m, i, c.mesh_tri_collider[nearest])};
    return 1;
  });
}

}  // namespace clothsim
