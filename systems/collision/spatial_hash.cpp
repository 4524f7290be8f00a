#include "systems/collision/spatial_hash.h"

#include <tbb/parallel_reduce.h>
#include <tbb/parallel_scan.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <limits>

#include "systems/parallel.h"

namespace clothsim {
namespace {

using namespace spatial_hash_detail;
inline constexpr Index prim_grain = 1024;

// In-place exclusive prefix sum; returns the total. Integer sums: the same result at any thread count.
Index exclusive_scan(std::vector<Index>& a, Index n) {
  return tbb::parallel_scan(
      tbb::blocked_range<Index>(0, n, 4096), Index(0),
      [&](const tbb::blocked_range<Index>& r, Index sum, bool final) {
        for (Index i = r.begin(); i != r.end(); ++i) {
          const Index v = a[i];
          if (final) a[i] = sum;
          sum += v;
        }
        return sum;
      },
      [](Index x, Index y) { return x + y; });
}

}  // namespace

Index next_prime(Index n) {
  auto is_prime = [](Index p) {
    if (p < 2) return false;
    for (Index d = 2; std::int64_t(d) * d <= p; ++d)
      if (p % d == 0) return false;
    return true;
  };
  while (!is_prime(n)) ++n;
  return n;
}

namespace {

// The cells [lo, hi] the prim's clipped box covers at 1/inv; false for a box outside the query bounds or beyond
// the representable cells (+-2^20 an axis: a cloth blown far away or to infinity, where cell_of would clamp and
// no cell size would shrink the count). Both passes of build_spatial_hash ask this, so they agree on every prim,
// and a larger cell brings every finite box within range, so the budget of choose_cell_and_count is always met.
bool hashed_cells(const CollisionScratch& s, Index slot, Real inv, Cell& lo, Cell& hi) {
  Aabb box;
  if (!clip(s.prim_box[slot], s.query_bounds, box) || !within_cell_range(box, inv)) return false;
  lo = cell_of(box.lo, inv);
  hi = cell_of(box.hi, inv);
  return true;
}

// Cells the prim covers at 1/inv, saturated at 2^32 (a finite box can span 2^21 cells an axis).
std::int64_t cells_of(const CollisionScratch& s, Index slot, Real inv) {
  Cell lo, hi;
  if (!hashed_cells(s, slot, inv, lo, hi)) return 0;
  const double n = double(hi.i - lo.i + 1) * double(hi.j - lo.j + 1) * double(hi.k - lo.k + 1);
  return std::int64_t(std::min(n, 4294967296.0));
}

// The cell this step hashes with: the model's, doubled until the entries fit entry_budget. A cloth that blows up
// within a frame swells its boxes before the frame's divergence check (exit 3) can stop the run; at the model's
// cell one box could cover 2^63 cells, and the entry arrays would exhaust memory before the check runs. Any
// cell size finds the same pairs (only the candidates per cell grow), and the choice depends on integer counts
// alone, so it is the same at any thread count. A sane step needs about 7 entries a prim. Each prim's count at
// the chosen cell is left in s.hash.prim_cells (every count fits: their sum is within the budget), so the hash
// does not count them again.
Real choose_cell_and_count(const CollisionModel& c, CollisionScratch& s) {
  const Index prims = c.cloth_prim_count;
  const std::int64_t entry_budget = 64 * std::int64_t(prims) + 65536;
  std::vector<Index>& counts = s.hash.prim_cells;
  Real inv = 1 / c.cell_size;
  for (int doubling = 0;; ++doubling, inv /= 2) {
    const std::int64_t total = tbb::parallel_reduce(
        tbb::blocked_range<Index>(0, prims, prim_grain), std::int64_t(0),
        [&](const tbb::blocked_range<Index>& r, std::int64_t sum) {
          for (Index slot = r.begin(); slot != r.end(); ++slot) {
            const std::int64_t n = cells_of(s, slot, inv);
            counts[slot] = Index(std::min<std::int64_t>(n, std::numeric_limits<Index>::max()));
            sum += n;
          }
          return sum;
        },
        std::plus<std::int64_t>());
    // 21 doublings bring any box within range (+-2^20 cells) to at most 8 cells; 63 is a bound, not a case.
    if (total <= entry_budget || doubling == 63) return inv;
  }
}

}  // namespace

void build_spatial_hash(const CollisionModel& c, CollisionScratch& s) {
  HashScratch& hs = s.hash;
  const Index prims = c.cloth_prim_count;
  const Real inv = choose_cell_and_count(c, s);
  hs.inv_cell = inv;
  const Index entries = exclusive_scan(hs.prim_cells, prims);
  hs.prim_cells[prims] = entries;
  hs.entry_count = entries;
  if (entries > Index(hs.entry_prim.size()) || hs.table_size == 0) {
    // Growth happens in the first steps only: later steps reuse the largest arrays seen.
    const std::size_t cap = std::size_t(entries) + entries / 2 + 64;
    for (auto* v : {&hs.entry_prim, &hs.scatter_prim, &hs.scatter_bucket}) v->resize(cap);
    hs.entry_cell.resize(cap);
    hs.scatter_cell.resize(cap);
    hs.table_size = next_prime(Index(2 * cap));
    hs.bucket_offset.resize(std::size_t(hs.table_size) + 1);
    hs.bucket_fill.resize(hs.table_size);
  }
  parallel_over(prims, prim_grain, [&](Index slot) {
    Cell lo, hi;
    if (!hashed_cells(s, slot, inv, lo, hi)) return;
    Index o = hs.prim_cells[slot];
    for (std::int64_t i = lo.i; i <= hi.i; ++i)
      for (std::int64_t j = lo.j; j <= hi.j; ++j)
        for (std::int64_t k = lo.k; k <= hi.k; ++k, ++o) {
          hs.scatter_prim[o] = slot;
          hs.scatter_cell[o] = pack(i, j, k);
          hs.scatter_bucket[o] = bucket_of(i, j, k, hs.table_size);
        }
  });
  parallel_over(hs.table_size, 1 << 14, [&](Index b) { hs.bucket_fill[b] = 0; });
  parallel_over(entries, 1 << 14, [&](Index e) {
    std::atomic_ref<Index>(hs.bucket_fill[hs.scatter_bucket[e]]).fetch_add(1, std::memory_order_relaxed);
  });
  parallel_over(hs.table_size, 1 << 14, [&](Index b) { hs.bucket_offset[b] = hs.bucket_fill[b]; });
  hs.bucket_offset[hs.table_size] = exclusive_scan(hs.bucket_offset, hs.table_size);
  parallel_over(hs.table_size, 1 << 14, [&](Index b) { hs.bucket_fill[b] = hs.bucket_offset[b]; });
  // The order inside a bucket depends on scheduling; every use of the entries sums integers or takes
  // minima, so results do not.
  parallel_over(entries, 1 << 14, [&](Index e) {
    const Index at = std::atomic_ref<Index>(hs.bucket_fill[hs.scatter_bucket[e]]).fetch_add(1, std::memory_order_relaxed);
    hs.entry_prim[at] = hs.scatter_prim[e];
    hs.entry_cell[at] = hs.scatter_cell[e];
  });
}

}  // namespace clothsim
