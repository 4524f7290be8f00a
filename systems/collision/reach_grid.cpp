#include "systems/collision/reach_grid.h"

#include <algorithm>

#include "systems/collision/broad_phase.h"

namespace clothsim {

using namespace spatial_hash_detail;

namespace {

// A box spanning more cells than this is taken as near without looking: a blown-up path, or a reach far smaller
// than the cloth's elements.
constexpr std::int64_t most_cells_a_box = 512;

std::int64_t cells_spanned(const Cell& lo, const Cell& hi) {
  return (hi.i - lo.i + 1) * (hi.j - lo.j + 1) * (hi.k - lo.k + 1);
}

}  // namespace

Real reach_of_a_particle(const Model& m, const CollisionScratch& s) {
  Real grow_by = 0;
  for (Index k = 0; k < m.collision.cloth_prim_count; ++k)
    grow_by = std::max(grow_by, (s.prim_box[k].hi - s.prim_box[k].lo).maxCoeff());
  return grow_by + m.collision.max_thickness;
}

void build_reach_grid(const State& in, const State& out, const std::vector<std::uint8_t>& flag, Real reach,
                      ReachGrid& g) {
  g.cells.clear();
  // With more than a quarter of the particles flagged the grid would skip little: its cells would only cost a sort.
  const std::size_t flagged = std::size_t(std::count(flag.begin(), flag.end(), std::uint8_t(1)));
  g.everywhere = !(reach > 0) || 4 * flagged > flag.size();
  g.inv_cell = g.everywhere ? 0 : 1 / reach;
  for (std::size_t i = 0; i < flag.size() && !g.everywhere; ++i) {
    if (flag[i] != 1) continue;
    Aabb box = swept_box(in.x[i], out.x[i]);
    box.lo.array() -= reach;
    box.hi.array() += reach;
    const Cell lo = cell_of(box.lo, g.inv_cell), hi = cell_of(box.hi, g.inv_cell);
    if (!within_cell_range(box, g.inv_cell) || cells_spanned(lo, hi) > most_cells_a_box) {
      g.everywhere = true;
      break;
    }
    for (std::int64_t a = lo.i; a <= hi.i; ++a)
      for (std::int64_t b = lo.j; b <= hi.j; ++b)
        for (std::int64_t c = lo.k; c <= hi.k; ++c) g.cells.push_back(pack(a, b, c));
  }
  std::sort(g.cells.begin(), g.cells.end());
  g.cells.erase(std::unique(g.cells.begin(), g.cells.end()), g.cells.end());
}

bool reaches(const ReachGrid& g, const Aabb& q) {
  if (g.everywhere || !within_cell_range(q, g.inv_cell)) return true;
  const Cell lo = cell_of(q.lo, g.inv_cell), hi = cell_of(q.hi, g.inv_cell);
  if (cells_spanned(lo, hi) > most_cells_a_box) return true;
  for (std::int64_t a = lo.i; a <= hi.i; ++a)
    for (std::int64_t b = lo.j; b <= hi.j; ++b)
      for (std::int64_t c = lo.k; c <= hi.k; ++c)
        if (std::binary_search(g.cells.begin(), g.cells.end(), pack(a, b, c))) return true;
  return false;
}

}  // namespace clothsim
