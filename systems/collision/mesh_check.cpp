#include "systems/collision/mesh_check.h"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>

#include "core/triangle_distance.h"
#include "systems/collision/collision_check.h"
#include "systems/reduce.h"

namespace clothsim {
namespace {

constexpr Index point_grain = 1024;

// The box of the mesh's finite vertices and its diagonal; diag = -1 when there is none.
struct MeshBox {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  Real diag = -1;
};

MeshBox mesh_box(std::span<const Vec3> verts, std::span<const Index> tri_index) {
  MeshBox b;
  b.lo = Vec3::Constant(std::numeric_limits<Real>::infinity());
  b.hi = -b.lo;
  for (const Index v : tri_index)
    if (verts[v].allFinite()) {
      b.lo = b.lo.cwiseMin(verts[v]);
      b.hi = b.hi.cwiseMax(verts[v]);
    }
  if ((b.lo.array() <= b.hi.array()).all()) b.diag = (b.hi - b.lo).norm();
  return b;
}

struct RayPlane {
  Vec3 u, v;  // orthonormal, both perpendicular to inside_ray_dir()
};

const RayPlane& ray_plane() {
  static const RayPlane plane = [] {
    const Vec3 u = inside_ray_dir().cross(Vec3(1, 0, 0)).normalized();
    return RayPlane{u, inside_ray_dir().cross(u)};
  }();
  return plane;
}

// Triangles' boxes in the ray's plane, padded by 1e-3 of the mesh's diagonal. Rounding in Moller-Trumbore can
// accept a crossing whose point projects just outside the triangle: with the test's 1e-10 parallel cut-off, by
// less than about 1e-5 of (distance to the triangle + its size), which the padding covers many times over for
// points within one diagonal of the mesh's box. Farther points test every triangle.
BoxGrid<2> ray_grid(std::span<const Vec3> verts, std::span<const Index> tri_index, const MeshBox& box) {
  const Index nt = Index(tri_index.size() / 3);
  const Real pad = 1e-3 * std::max(box.diag, Real(0));
  std::vector<Vec2> lo(nt), hi(nt);
  for (Index t = 0; t < nt; ++t) {
    const Vec2 a = project_along_inside_ray(verts[tri_index[3 * t]]),
               b = project_along_inside_ray(verts[tri_index[3 * t + 1]]),
               c = project_along_inside_ray(verts[tri_index[3 * t + 2]]);
    lo[t] = a.cwiseMin(b).cwiseMin(c) - Vec2::Constant(pad);
    hi[t] = a.cwiseMax(b).cwiseMax(c) + Vec2::Constant(pad);
  }
  return build_box_grid<2>(lo, hi, check_grid_max_cells);
}

// What a point found for the distance: the smallest distance over the triangles it tested, and whether those
// were all of the mesh's.
struct Nearest {
  Real d;
  bool complete;
};

}  // namespace

template <int D>
BoxGrid<D> build_box_grid(std::span<const typename BoxGrid<D>::Point> box_lo,
                          std::span<const typename BoxGrid<D>::Point> box_hi, Index max_cells) {
  using Point = typename BoxGrid<D>::Point;
  using Cell = typename BoxGrid<D>::Cell;
  BoxGrid<D> g;
  const Index count = Index(box_lo.size());
  g.item_first.assign(count, Cell{});
  g.cell_offset.assign(1, 0);
  std::vector<char> binned(count, 0);
  Point lo = Point::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  Real size_sum = 0;
  Index finite = 0;
  for (Index k = 0; k < count; ++k) {
    if (!box_lo[k].allFinite() || !box_hi[k].allFinite()) continue;
    binned[k] = 1;
    lo = lo.cwiseMin(box_lo[k]);
    hi = hi.cwiseMax(box_hi[k]);
    size_sum += (box_hi[k] - box_lo[k]).maxCoeff();
    ++finite;
  }
  const Point extent = hi - lo;
  // Nothing finite, or an extent past double's range: every item is tested by every query (exact, if slow).
  if (finite == 0 || !extent.allFinite() || !std::isfinite(size_sum)) {
    g.unbinned.resize(count);
    for (Index k = 0; k < count; ++k) g.unbinned[k] = k;
    return g;
  }
  for (Index k = 0; k < count; ++k)
    if (!binned[k]) g.unbinned.push_back(k);
  g.lo = lo;
  // Cells of the mean box size; from the extent when every box is a point, one cell when all are one point.
  g.h = size_sum / finite;
  if (!(g.h > 0)) g.h = extent.maxCoeff() / 64;
  if (!(g.h > 0)) g.h = 1;
  auto cell_range = [&](Index k, Cell& a, Cell& b) { g.cell_range(box_lo[k], box_hi[k], a, b); };
  std::int64_t entries = 0;
  for (;;) {
    Real cells = 1;
    for (int d = 0; d < D; ++d) cells *= std::floor(extent[d] / g.h) + 1;
    if (cells > max_cells) {
      g.h *= std::pow(cells / max_cells, 1.0 / D) * 1.01;
      continue;
    }
    for (int d = 0; d < D; ++d) g.n[d] = Index(std::floor(extent[d] / g.h) + 1);
    // A few boxes far larger than the mean would fill many cells each: coarser cells bound the entries.
    entries = 0;
    Cell a, b;
    for (Index k = 0; k < count; ++k) {
      if (!binned[k]) continue;
      cell_range(k, a, b);
      std::int64_t span = 1;
      for (int d = 0; d < D; ++d) span *= b[d] - a[d] + 1;
      entries += span;
    }
    if (entries <= 32 * std::int64_t(finite) + max_cells) break;
    g.h *= 2;
  }
  Index cells = 1;
  for (int d = 0; d < D; ++d) cells *= g.n[d];
  g.cell_offset.assign(cells + 1, 0);
  Cell a, b;
  for (Index k = 0; k < count; ++k) {
    if (!binned[k]) continue;
    cell_range(k, a, b);
    g.item_first[k] = a;
    g.for_each_cell(a, b, [&](const Cell& c) { ++g.cell_offset[g.cell_id(c) + 1]; });
  }
  for (Index c = 0; c < cells; ++c) g.cell_offset[c + 1] += g.cell_offset[c];
  // Filled in item order, so each cell lists its items ascending whatever the build.
  g.cell_item.resize(entries);
  std::vector<Index> next(g.cell_offset.begin(), g.cell_offset.end() - 1);
  for (Index k = 0; k < count; ++k) {
    if (!binned[k]) continue;
    cell_range(k, a, b);
    g.for_each_cell(a, b, [&](const Cell& c) { g.cell_item[next[g.cell_id(c)]++] = k; });
  }
  return g;
}

template BoxGrid<2> build_box_grid<2>(std::span<const BoxGrid<2>::Point>, std::span<const BoxGrid<2>::Point>, Index);
template BoxGrid<3> build_box_grid<3>(std::span<const BoxGrid<3>::Point>, std::span<const BoxGrid<3>::Point>, Index);

Vec2 project_along_inside_ray(const Vec3& p) { return Vec2(p.dot(ray_plane().u), p.dot(ray_plane().v)); }

BoxGrid<2> build_ray_grid(std::span<const Vec3> verts, std::span<const Index> tri_index) {
  return ray_grid(verts, tri_index, mesh_box(verts, tri_index));
}

BoxGrid<3> build_distance_grid(std::span<const Vec3> verts, std::span<const Index> tri_index) {
  const Index nt = Index(tri_index.size() / 3);
  std::vector<Vec3> lo(nt), hi(nt);
  for (Index t = 0; t < nt; ++t) {
    const Vec3 &a = verts[tri_index[3 * t]], &b = verts[tri_index[3 * t + 1]], &c = verts[tri_index[3 * t + 2]];
    lo[t] = a.cwiseMin(b).cwiseMin(c);
    hi[t] = a.cwiseMax(b).cwiseMax(c);
  }
  return build_box_grid<3>(lo, hi, check_grid_max_cells);
}

Index count_points_inside(std::span<const Vec3> points, std::span<const Vec3> verts, std::span<const Index> tri_index) {
  const Index nt = Index(tri_index.size() / 3);
  const MeshBox box = mesh_box(verts, tri_index);
  const BoxGrid<2> g = ray_grid(verts, tri_index, box);
  auto per_point = [&](Index i) -> Index {
    const Vec3& p = points[i];
    const Vec3 q = inside_ray_end(p);
    Index crossings = 0;
    auto test = [&](Index t) {
      const Index* v = &tri_index[3 * t];
      crossings += segment_crosses_triangle(p, q, verts[v[0]], verts[v[1]], verts[v[2]]);
    };
    // Beyond the padding's reach (far from the mesh, or not finite): every triangle.
    if (!((p - p.cwiseMax(box.lo).cwiseMin(box.hi)).norm() <= box.diag)) {
      for (Index t = 0; t < nt; ++t) test(t);
      return crossings % 2;
    }
    for (const Index t : g.unbinned) test(t);
    const Vec2 uv = project_along_inside_ray(p);
    const Index i0 = g.axis_cell(uv[0], 0), i1 = g.axis_cell(uv[1], 1);
    if (i0 < 0 || i1 < 0 || i0 >= g.n[0] || i1 >= g.n[1]) return crossings % 2;
    const Index id = g.cell_id({i0, i1});
    for (Index k = g.cell_offset[id]; k < g.cell_offset[id + 1]; ++k) test(g.cell_item[k]);
    return crossings % 2;
  };
  return deterministic_reduce(Index(points.size()), point_grain, Index(0), per_point, std::plus<Index>());
}

// Rounds of growing radius r: each point tests the triangles whose boxes meet the cube of cells within r of it,
// so a point whose nearest triangle lies within r finds it. The smallest value found is then exact once it is
// <= r (every point nearer than it would have found its own); otherwise r becomes that value (one more round
// ends it), or doubles while nothing is found.
Real min_point_distance(std::span<const Vec3> points, std::span<const Vec3> verts, std::span<const Index> tri_index) {
  const Index nt = Index(tri_index.size() / 3), np = Index(points.size());
  if (nt == 0 || np == 0) return 1e300;
  const BoxGrid<3> g = build_distance_grid(verts, tri_index);
  Real grid_scale = 0;
  for (int k = 0; k < 3; ++k) grid_scale = std::max({grid_scale, std::abs(g.lo[k]), std::abs(g.lo[k] + g.n[k] * g.h)});
  auto distance = [&](const Vec3& p, Index t) {
    const Index* v = &tri_index[3 * t];
    return point_triangle_distance(p, verts[v[0]], verts[v[1]], verts[v[2]]);
  };
  auto every_triangle = [&](const Vec3& p) -> Nearest {
    Real best = 1e300;
    for (Index t = 0; t < nt; ++t) best = std::min(best, distance(p, t));
    return {best, true};
  };
  auto search = [&](Index i, Real r) -> Nearest {
    const Vec3& p = points[i];
    if (!p.allFinite()) return every_triangle(p);
    Real best = 1e300;
    for (const Index t : g.unbinned) best = std::min(best, distance(p, t));
    if (g.n[0] == 0) return {best, true};  // no triangle is binned: the unbinned were all of them
    // Padded for rounding: a computed distance <= r may sit a few ulps past the box's reach.
    const Real pad = r * (1 + 1e-9) + 1e-9 * (grid_scale + p.cwiseAbs().maxCoeff());
    BoxGrid<3>::Cell a, b;
    bool whole = true;
    Real cells = 1;
    for (int k = 0; k < 3; ++k) {
      a[k] = std::max(g.axis_cell(p[k] - pad, k), Index(0));
      b[k] = std::min(g.axis_cell(p[k] + pad, k), g.n[k] - 1);
      if (a[k] > b[k]) return {best, false};  // no binned triangle within r
      whole = whole && a[k] == 0 && b[k] == g.n[k] - 1;
      cells *= b[k] - a[k] + 1;
    }
    if (cells > nt) return every_triangle(p);  // cheaper than the cells' lists
    g.for_each_item(a, b, [&](Index t) { best = std::min(best, distance(p, t)); });
    return {best, whole};
  };
  auto join = [](const Nearest& x, const Nearest& y) { return Nearest{std::min(x.d, y.d), x.complete && y.complete}; };
  for (Real r = g.h;;) {
    const Nearest found = deterministic_reduce(np, point_grain, Nearest{1e300, true},
                                               [&](Index i) { return search(i, r); }, join);
    if (found.d <= r || found.complete) return found.d;
    r = found.d < 1e300 ? found.d : 2 * r;
  }
}

}  // namespace clothsim
