#include "systems/collision/collider_guard.h"

#include <limits>

#include "systems/collision/broad_phase.h"
#include "systems/collision/colliders.h"
#include "systems/collision/response.h"
#include "systems/reduce.h"

namespace clothsim {

bool behind_collider_triangle(const Model& m, const CollisionScratch& s, Index tri, const Vec3& x,
                              const TrianglePoint& q) {
  const CollisionModel& c = m.collision;
  const Index* v = &c.mesh_tri_index[3 * tri];
  const Vec3 &a = s.collider_x1[v[0]], &b = s.collider_x1[v[1]], &cc = s.collider_x1[v[2]];
  const Vec3 face = (b - a).cross(cc - a);
  if (!(face.squaredNorm() > 0)) return false;
  // Which corners q lies on: all three weights positive is the face, one zero an edge, two a corner.
  Vec3 normal = Vec3::Zero();
  int corners = 0;
  for (int k = 0; k < 3; ++k)
    if (q.weights[k] > 0) {
      normal += collider_vertex_normal(c, s, v[k]);
      ++corners;
    }
  if (corners == 3 || corners == 0) normal = face;
  return (x - q.point).dot(normal) < 0;
}

namespace {

// The collider-mesh triangle nearest to x within `reach` (none: tri < 0), its closest point q, and whether x lies
// behind it.
struct Nearest {
  Index tri = -1;
  TrianglePoint q;
  Real distance = 0;
  bool behind = false;
  // Signed distance to the surface, m: negative behind it; +infinity with no triangle in reach.
  Real signed_distance() const {
    return tri < 0 ? std::numeric_limits<Real>::infinity() : behind ? -distance : distance;
  }
};

Nearest nearest_surface(const Model& m, const CollisionScratch& s, const Vec3& x, Real reach) {
  const CollisionModel& c = m.collision;
  const Aabb box{Vec3(x.array() - reach), Vec3(x.array() + reach)};
  Real best = reach * reach;
  Nearest n;
  query_bvh(c.collider_tree, s.collider_node_box, box, [&](Index slot) {
    const Index tri = c.prim[slot] - m.tri_count;
    const Index* v = &c.mesh_tri_index[3 * tri];
    const TrianglePoint q =
        closest_point_and_weights(x, s.collider_x1[v[0]], s.collider_x1[v[1]], s.collider_x1[v[2]]);
    const Real d2 = (x - q.point).squaredNorm();
    // Ties go to the lower triangle, so the visiting order does not matter.
    if (d2 < best || (d2 == best && n.tri >= 0 && tri < n.tri)) {
      best = d2;
      n.tri = tri;
      n.q = q;
    }
  });
  if (n.tri < 0) return n;
  n.distance = std::sqrt(best);
  n.behind = n.distance > 0 && behind_collider_triangle(m, s, n.tri, x, n.q);
  return n;
}

// Bisections of the way back: 2^-20 of a few millimetres is far below any thickness.
constexpr int way_back_bisections = 20;

}  // namespace

Index guard_collider_surfaces(const Model& m, State& out, const CollisionScratch& s, Real h) {
  const CollisionModel& c = m.collision;
  if (c.mesh_tri_collider.empty() || s.collider_node_box.empty()) return 0;
  return deterministic_sum(m.particle_count, particle_grain, Index(0), [&](Index i) -> Index {
    if (m.particle_inv_mass[i] == 0) return 0;
    const Vec3 x = out.x[i];
    const Real reach = collider_guard_reach * m.particle_thickness[i];
    const Real margin = collider_guard_margin * m.particle_thickness[i];
    const Nearest inside = nearest_surface(m, s, x, reach);
    if (!inside.behind) return 0;
    // Back the way the rounds carried it, towards where the collide stage left it, to the first point the margin
    // outside: that way is clear of the cloth layers beside it, where the nearest surface point may lie across
    // them. When the collide stage itself left it closer (a pinch), onto the nearest surface instead.
    Vec3 to = inside.q.point + margin * (inside.q.point - x) / inside.distance;
    if (!s.collided_x.empty() && nearest_surface(m, s, s.collided_x[i], reach).signed_distance() >= margin) {
      const Vec3 way = s.collided_x[i] - x;
      Real lo = 0, hi = 1;
      for (int k = 0; k < way_back_bisections; ++k) {
        const Real mid = (lo + hi) / 2;
        (nearest_surface(m, s, x + mid * way, reach).signed_distance() >= margin ? hi : lo) = mid;
      }
      to = x + hi * way;
    }
    const Nearest at = nearest_surface(m, s, to, reach);
    const Nearest& held = at.tri >= 0 ? at : inside;
    const Vec3 u = at.tri >= 0 && at.distance > 0 && !at.behind ? Vec3((to - at.q.point) / at.distance)
                                                                 : Vec3((inside.q.point - x) / inside.distance);
    out.x[i] = to;
    const Real vn = out.v[i].dot(u);
    if (vn < 0) out.v[i] -= vn * u;
    // Held there from now on: by the strain limit's planes in this step, by the next solve's filter after it.
    if (out.contact.empty()) return 1;
    // corners() reads only the collider's own positions for a collider prim.
    const Vec3 moving = prim_velocity(corners(m, out, out, s, m.tri_count + held.tri), held.q.weights.data(), h);
    out.contact[i] = {u, moving, collider_friction(m, i, c.mesh_tri_collider[held.tri])};
    return 1;
  });
}

}  // namespace clothsim
