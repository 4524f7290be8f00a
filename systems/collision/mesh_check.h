#pragma once
// Exact point queries against a collider mesh for the independent checks (collision_check.h): the same answer as
// testing every triangle, found through uniform grids of their own. They share no code with the collide stage's
// broad phase (spatial_hash, bvh), so that a fault there cannot hide itself in the check.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "core/math.h"

namespace clothsim {

// Items (triangles) binned by their boxes into the cells of a uniform D-dimensional grid: an item is listed in
// every cell its box overlaps, in ascending order.
template <int D>
struct BoxGrid {
  using Point = Eigen::Matrix<Real, D, 1, Eigen::DontAlign>;
  using Cell = std::array<Index, D>;
  Point lo = Point::Zero();        // corner of cell (0, ..., 0), m
  Real h = 1;                      // cell side, m
  Cell n{};                        // cells along each axis; all 0 when no box is finite
  std::vector<Index> cell_offset;  // CSR, cell (i, j, k) at i + n0 (j + n1 k) (cells + 1)
  std::vector<Index> cell_item;    // (entries)
  std::vector<Cell> item_first;    // each item's lowest cell, so that a query visits it once (items)
  std::vector<Index> unbinned;     // items whose box is not finite: every query visits them

  // Cell coordinate of x along axis k, clamped to [-1, n[k]] so that far values stay representable.
  Index axis_cell(Real x, int k) const {
    const Real c = std::floor((x - lo[k]) / h);
    return c < -1 ? -1 : c > n[k] ? n[k] : Index(c);
  }
  Index cell_id(const Cell& c) const {
    Index id = c[D - 1];
    for (int k = D - 2; k >= 0; --k) id = id * n[k] + c[k];
    return id;
  }
  // The cells [a, b] of box [box_lo, box_hi] within the grid; empty (a[k] > b[k]) when it misses the grid.
  void cell_range(const Point& box_lo, const Point& box_hi, Cell& a, Cell& b) const {
    for (int k = 0; k < D; ++k) {
      a[k] = std::max(axis_cell(box_lo[k], k), Index(0));
      b[k] = std::min(axis_cell(box_hi[k], k), n[k] - 1);
    }
  }
  // Calls f(item) once for each item listed in the cells [a, b]: in the first cell of the range that lists it.
  template <class F>
  void for_each_item(const Cell& a, const Cell& b, F&& f) const {
    for_each_cell(a, b, [&](const Cell& c) {
      const Index id = cell_id(c);
      for (Index e = cell_offset[id]; e < cell_offset[id + 1]; ++e) {
        const Index item = cell_item[e];
        bool first = true;
        for (int k = 0; k < D; ++k) first = first && c[k] == std::max(item_first[item][k], a[k]);
        if (first) f(item);
      }
    });
  }
  template <class F>
  void for_each_cell(const Cell& a, const Cell& b, F&& f) const {
    if constexpr (D == 2) {
      for (Index j = a[1]; j <= b[1]; ++j)
        for (Index i = a[0]; i <= b[0]; ++i) f(Cell{i, j});
    } else {
      for (Index k = a[2]; k <= b[2]; ++k)
        for (Index j = a[1]; j <= b[1]; ++j)
          for (Index i = a[0]; i <= b[0]; ++i) f(Cell{i, j, k});
    }
  }
};

// At most ~4M cells (16 MB of offsets): 4 mm cells over a 2 m body in 3D, far finer in the ray's 2D plane.
inline constexpr Index check_grid_max_cells = Index(1) << 22;

// Bins the boxes [box_lo[k], box_hi[k]] into cells about the size of the mean box (its longest side), growing the
// cells until there are at most max_cells of them and each box overlaps a few on average.
template <int D>
BoxGrid<D> build_box_grid(std::span<const typename BoxGrid<D>::Point> box_lo,
                          std::span<const typename BoxGrid<D>::Point> box_hi, Index max_cells);

// The ray of the inside test: a vertex is inside when segment p -> inside_ray_end(p) crosses the mesh an odd
// number of times. A long ray in a direction unlikely to graze mesh edges.
inline const Vec3& inside_ray_dir() {
  static const Vec3 dir = Vec3(0.5772, 0.6180, 0.5330).normalized();
  return dir;
}
inline Vec3 inside_ray_end(const Vec3& p) { return p + inside_ray_dir() * 1e4; }

// p's coordinates in the plane perpendicular to the inside ray: a segment can cross a triangle only where its
// projection falls in the triangle's.
Vec2 project_along_inside_ray(const Vec3& p);

// The grids of the two queries for mesh (verts, tri_index: 3 per triangle), exposed so that tests can put
// points on cell borders: triangles' boxes projected along the inside ray (padded for rounding), and their 3D boxes.
BoxGrid<2> build_ray_grid(std::span<const Vec3> verts, std::span<const Index> tri_index);
BoxGrid<3> build_distance_grid(std::span<const Vec3> verts, std::span<const Index> tri_index);

// Points with an odd number of crossings of the mesh along the inside ray (segment_crosses_triangle): inside a
// closed mesh. The same count as testing every triangle, at any thread count.
Index count_points_inside(std::span<const Vec3> points, std::span<const Vec3> verts, std::span<const Index> tri_index);

// The smallest point_triangle_distance from a point to a triangle of the mesh, m; 1e300 without points or
// triangles. The same value as testing every pair, at any thread count.
Real min_point_distance(std::span<const Vec3> points, std::span<const Vec3> verts, std::span<const Index> tri_index);

}  // namespace clothsim
