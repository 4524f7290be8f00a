#include "systems/collision/push_out.h"

#include <limits>

#include "systems/collision/collision_check.h"
#include "systems/parallel.h"
#include "systems/collision/proximity.h"

namespace clothsim {
namespace {

bool closed_mesh(const ColliderInfo& ci) {
  return (ci.shape == ColliderShape::mesh || ci.shape == ColliderShape::sequence) && ci.closed;
}

// Parity of crossings along a long ray, in a direction unlikely to graze mesh edges, against the collider at
// the start of the step.
bool inside_by_parity(const Model& m, const CollisionScratch& s, const ColliderInfo& ci, const Vec3& p) {
  const Vec3 far = p + Vec3(-0.4127, 0.7071, 0.5744).normalized() * 1e4;
  int crossings = 0;
  for (Index t = ci.tri_begin; t < ci.tri_end; ++t) {
    const Index* v = &m.collision.mesh_tri_index[3 * t];
    crossings += segment_crosses_triangle(p, far, s.collider_x0[v[0]], s.collider_x0[v[1]], s.collider_x0[v[2]]);
  }
  return crossings % 2 == 1;
}

void scan_inside(const Model& m, const State& in, CollisionScratch& s) {
  for (Index c = 0; c < Index(m.collision.colliders.size()); ++c) {
    const ColliderInfo& ci = m.collision.colliders[c];
    if (!closed_mesh(ci) || ci.vertex_end == ci.vertex_begin) continue;
    Aabb box{s.collider_x0[ci.vertex_begin], s.collider_x0[ci.vertex_begin]};
    for (Index v = ci.vertex_begin; v < ci.vertex_end; ++v) {
      box.lo = box.lo.cwiseMin(s.collider_x0[v]);
      box.hi = box.hi.cwiseMax(s.collider_x0[v]);
    }
    parallel_over(m.particle_count, particle_grain, [&](Index i) {
      if (m.particle_inv_mass[i] == 0 || s.deep_collider[i] >= 0) return;
      const Vec3& p = in.x[i];
      if ((p.array() < box.lo.array()).any() || (p.array() > box.hi.array()).any()) return;
      if (inside_by_parity(m, s, ci, p)) s.deep_collider[i] = std::int32_t(c);
    });
  }
}

}  // namespace

void push_out_deep_vertices(const Model& m, const State& in, State& out, CollisionScratch& s, Real h) {
  bool any = false;
  for (const ColliderInfo& ci : m.collision.colliders) any = any || closed_mesh(ci);
  if (!any) return;
  if (!s.deep_scanned) {
    scan_inside(m, in, s);
    s.deep_scanned = true;
  }
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    const std::int32_t c = s.deep_collider[i];
    if (c < 0) return;
    const ColliderInfo& ci = m.collision.colliders[c];
    // Nearest point of the surface at the end of the step, and the outward normal of its triangle.
    Real best = std::numeric_limits<Real>::infinity();
    Vec3 nearest = out.x[i], normal(0, 1, 0);
    for (Index t = ci.tri_begin; t < ci.tri_end; ++t) {
      const Index* v = &m.collision.mesh_tri_index[3 * t];
      const Vec3 &a = s.collider_x1[v[0]], &b = s.collider_x1[v[1]], &cc = s.collider_x1[v[2]];
      const Vec3 q = closest_point_on_triangle(out.x[i], a, b, cc);
      const Real d2 = (out.x[i] - q).squaredNorm();
      if (d2 < best) {
        best = d2;
        nearest = q;
        normal = (b - a).cross(cc - a);
      }
    }
    const Vec3 offset = nearest - out.x[i];  // towards the surface
    const Real depth = offset.norm();
    // Past the nearest triangle's plane: the cloth dynamics or an earlier push already brought it out.
    if (!(depth > 0) || offset.dot(normal) <= 0) {
      s.deep_collider[i] = -1;
      return;
    }
    const Vec3 u = offset / depth;
    const Real need = depth + m.particle_thickness[i], most = deep_push_speed * h;
    out.x[i] += std::min(need, most) * u;
    const Real vn = out.v[i].dot(u);
    if (vn < 0) out.v[i] -= vn * u;
    if (need <= most) s.deep_collider[i] = -1;
  });
}

}  // namespace clothsim
