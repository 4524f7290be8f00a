#include "systems/collision/collision_check.h"

#include <algorithm>

#include "systems/collision/mesh_check.h"
#include "systems/collision/proximity.h"
#include "systems/reduce.h"

namespace clothsim {
namespace {

constexpr Index vertex_grain = 1024;

template <class T, class PerVertex, class Join>
T reduce_vertices(Index n, T init, PerVertex&& f, Join&& join) {
  return deterministic_reduce(n, vertex_grain, init, f, join);
}

std::span<const Index> collider_tris(const Model& m, const ColliderInfo& ci) {
  return std::span<const Index>(m.collision.mesh_tri_index).subspan(3 * ci.tri_begin, 3 * (ci.tri_end - ci.tri_begin));
}

}  // namespace

bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 dir = q - p, e1 = b - a, e2 = c - a;
  const Vec3 pv = dir.cross(e2);
  const Real det = e1.dot(pv);
  // Parallel or coplanar (within rounding): a crossing needs the segment to pierce the plane.
  if (std::abs(det) <= 1e-10 * dir.norm() * e1.norm() * e2.norm()) return false;
  const Real inv = 1 / det;
  const Vec3 tv = p - a;
  const Real u = tv.dot(pv) * inv;
  if (u < 0 || u > 1) return false;
  const Vec3 qv = tv.cross(e1);
  const Real v = dir.dot(qv) * inv;
  if (v < 0 || u + v > 1) return false;
  const Real t = e2.dot(qv) * inv;
  return t >= 0 && t <= 1;
}

// Meshes go through mesh_check.h's grids, which give the same value as testing every triangle.
Real min_collider_distance(const Model& m, std::span<const Vec3> x, const CollisionScratch& s, Index c) {
  const ColliderInfo& ci = m.collision.colliders[c];
  if (ci.shape != ColliderShape::sphere && ci.shape != ColliderShape::plane)
    return min_point_distance(x.first(m.particle_count), s.collider_x1, collider_tris(m, ci));
  auto per_vertex = [&](Index i) -> Real {
    if (ci.shape == ColliderShape::sphere) return (x[i] - ci.center).norm() - ci.radius;
    return ci.normal.dot(x[i] - ci.point);
  };
  return reduce_vertices(m.particle_count, Real(1e300), per_vertex, [](Real a, Real b) { return std::min(a, b); });
}

Index count_inside(const Model& m, std::span<const Vec3> x, const CollisionScratch& s, Index c) {
  const ColliderInfo& ci = m.collision.colliders[c];
  if (ci.shape != ColliderShape::sphere && ci.shape != ColliderShape::plane)
    return ci.closed ? count_points_inside(x.first(m.particle_count), s.collider_x1, collider_tris(m, ci)) : 0;
  auto per_vertex = [&](Index i) -> Index {
    if (ci.shape == ColliderShape::sphere) return (x[i] - ci.center).norm() < ci.radius;
    return ci.normal.dot(x[i] - ci.point) < 0;
  };
  return reduce_vertices(m.particle_count, Index(0), per_vertex, [](Index a, Index b) { return a + b; });
}

// A pair is tested when the x ranges of the triangles' boxes overlap (the pairs of a sweep along x), so the count
// does not depend on the grid. The grid (mesh_check.h) only skips pairs whose boxes, padded by 1e-3 of their
// diagonals, are apart: rounding in segment_crosses_triangle moves a crossing by ~1e-5 of the sizes involved at
// most (mesh_check.cpp), so such a pair never crosses.
Index count_intersecting_triangles(const Model& m, std::span<const Vec3> x) {
  const Index n = m.tri_count;
  std::vector<Vec3> lo(n), hi(n), pad_lo(n), pad_hi(n);
  for (Index t = 0; t < n; ++t) {
    const Vec3 &a = x[m.tri_index[3 * t]], &b = x[m.tri_index[3 * t + 1]], &c = x[m.tri_index[3 * t + 2]];
    lo[t] = a.cwiseMin(b).cwiseMin(c);
    hi[t] = a.cwiseMax(b).cwiseMax(c);
    const Vec3 pad = Vec3::Constant(1e-3 * (hi[t] - lo[t]).norm());
    pad_lo[t] = lo[t] - pad;
    pad_hi[t] = hi[t] + pad;
  }
  const BoxGrid<3> g = build_box_grid<3>(pad_lo, pad_hi, check_grid_max_cells);
  std::vector<char> unbinned(n, 0);
  for (const Index t : g.unbinned) unbinned[t] = 1;
  auto test_pair = [&](Index a, Index b) -> Index {
    if (!(lo[b].x() <= hi[a].x() && lo[a].x() <= hi[b].x())) return 0;
    if (!boxes_overlap({pad_lo[a], pad_hi[a]}, {pad_lo[b], pad_hi[b]})) return 0;
    const Index* pa = &m.tri_index[3 * a];
    const Index* pb = &m.tri_index[3 * b];
    bool adjacent = false;  // sharing a corner, or a corner sewn to one of the other's (a seam)
    for (int u = 0; u < 3; ++u)
      for (int w = 0; w < 3; ++w) adjacent = adjacent || m.collision.joined(pa[u], pb[w]);
    if (adjacent) return 0;
    bool cross = false;
    for (int e = 0; e < 3 && !cross; ++e) {
      cross = segment_crosses_triangle(x[pa[e]], x[pa[(e + 1) % 3]], x[pb[0]], x[pb[1]], x[pb[2]]) ||
              segment_crosses_triangle(x[pb[e]], x[pb[(e + 1) % 3]], x[pa[0]], x[pa[1]], x[pa[2]]);
    }
    return cross;
  };
  // Each pair once, from its lower triangle: in the first cell both list, or directly when either is unbinned.
  auto per_tri = [&](Index a) -> Index {
    Index hits = 0;
    if (unbinned[a]) {
      for (Index b = a + 1; b < n; ++b) hits += test_pair(a, b);
      return hits;
    }
    for (const Index b : g.unbinned)
      if (b > a) hits += test_pair(a, b);
    BoxGrid<3>::Cell ca, cb;
    g.cell_range(pad_lo[a], pad_hi[a], ca, cb);
    const BoxGrid<3>::Cell& fa = g.item_first[a];
    g.for_each_cell(ca, cb, [&](const BoxGrid<3>::Cell& c) {
      const Index id = g.cell_id(c);
      for (Index e = g.cell_offset[id]; e < g.cell_offset[id + 1]; ++e) {
        const Index b = g.cell_item[e];
        if (b <= a) continue;
        const BoxGrid<3>::Cell& fb = g.item_first[b];
        if (c[0] != std::max(fa[0], fb[0]) || c[1] != std::max(fa[1], fb[1]) || c[2] != std::max(fa[2], fb[2])) continue;
        hits += test_pair(a, b);
      }
    });
    return hits;
  };
  return reduce_vertices(n, Index(0), per_tri, [](Index a, Index b) { return a + b; });
}

Index count_collider_crossings(const Model& m, std::span<const Vec3> x, const CollisionScratch& s, Index c) {
  const ColliderInfo& ci = m.collision.colliders[c];
  if ((ci.shape != ColliderShape::mesh && ci.shape != ColliderShape::sequence) || ci.closed) return 0;
  // Collider triangles binned by their boxes (mesh_check.h's grid); a cloth triangle tests those whose boxes meet
  // its own, each once: in the first cell of its own box that lists it.
  const Index n = ci.tri_end - ci.tri_begin;
  std::vector<Vec3> lo(n), hi(n);
  for (Index k = 0; k < n; ++k) {
    const Index* v = &m.collision.mesh_tri_index[3 * (ci.tri_begin + k)];
    const Vec3 &a = s.collider_x1[v[0]], &b = s.collider_x1[v[1]], &cc = s.collider_x1[v[2]];
    lo[k] = a.cwiseMin(b).cwiseMin(cc);
    hi[k] = a.cwiseMax(b).cwiseMax(cc);
  }
  const BoxGrid<3> g = build_box_grid<3>(lo, hi, check_grid_max_cells);
  auto per_tri = [&](Index t) -> Index {
    const Index* p = &m.tri_index[3 * t];
    const Aabb own{x[p[0]].cwiseMin(x[p[1]]).cwiseMin(x[p[2]]), x[p[0]].cwiseMax(x[p[1]]).cwiseMax(x[p[2]])};
    auto crosses = [&](Index k) -> Index {
      if (!boxes_overlap(own, {lo[k], hi[k]})) return 0;
      const Index* v = &m.collision.mesh_tri_index[3 * (ci.tri_begin + k)];
      const Vec3 &a = s.collider_x1[v[0]], &b = s.collider_x1[v[1]], &cc = s.collider_x1[v[2]];
      bool cross = false;
      for (int e = 0; e < 3 && !cross; ++e)
        cross = segment_crosses_triangle(x[p[e]], x[p[(e + 1) % 3]], a, b, cc) ||
                segment_crosses_triangle(s.collider_x1[v[e]], s.collider_x1[v[(e + 1) % 3]], x[p[0]], x[p[1]], x[p[2]]);
      return cross;
    };
    Index hits = 0;
    if (!own.lo.allFinite() || !own.hi.allFinite()) {
      for (Index k = 0; k < n; ++k) hits += crosses(k);
      return hits;
    }
    for (const Index k : g.unbinned) hits += crosses(k);
    BoxGrid<3>::Cell ca, cb;
    g.cell_range(own.lo, own.hi, ca, cb);
    g.for_each_item(ca, cb, [&](Index k) { hits += crosses(k); });
    return hits;
  };
  return reduce_vertices(m.tri_count, Index(0), per_tri, [](Index a, Index b) { return a + b; });
}

}  // namespace clothsim
