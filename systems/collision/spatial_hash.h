#pragma once
// Spatial hash after Teschner et al. 2003 (§4: cell = mean edge length, h(i,j,k) = (i p1 xor j p2 xor k p3)
// mod n with p1..p3 = 73856093, 19349663, 83492791, n prime) and Kelager 2006. Rebuilt every step by parallel
// kernels with no locks: count cells per prim, scan, write entries, count per bucket with integer atomics, scan,
// scatter into contiguous bucket ranges. Entries keep their cell, so cells that share a bucket are told apart.
#include <cmath>

#include "core/model.h"
#include "systems/collision/proximity.h"

namespace clothsim {

namespace spatial_hash_detail {
inline constexpr std::int64_t cell_bias = std::int64_t(1) << 20;  // cell coordinates within +-2^20 per axis

struct Cell {
  std::int64_t i, j, k;
};
inline Cell cell_of(const Vec3& p, Real inv_cell) {
  auto f = [&](Real x) {
    return std::clamp<std::int64_t>(std::int64_t(std::floor(x * inv_cell)), -cell_bias + 1, cell_bias - 1);
  };
  return {f(p.x()), f(p.y()), f(p.z())};
}
inline std::int64_t pack(std::int64_t i, std::int64_t j, std::int64_t k) {
  return ((i + cell_bias) << 42) | ((j + cell_bias) << 21) | (k + cell_bias);
}
inline Index bucket_of(std::int64_t i, std::int64_t j, std::int64_t k, Index table_size) {
  const std::uint64_t h = (std::uint64_t(i) * 73856093u) ^ (std::uint64_t(j) * 19349663u) ^
                          (std::uint64_t(k) * 83492791u);
  return Index(h % std::uint64_t(table_size));
}
// Whether box's cells at 1/inv lie within +-cell_bias an axis, where cell_of does not clamp (false for NaN or inf).
inline bool within_cell_range(const Aabb& box, Real inv_cell) {
  const Real limit = Real(cell_bias - 1);
  return (box.lo * inv_cell).cwiseAbs().maxCoeff() < limit && (box.hi * inv_cell).cwiseAbs().maxCoeff() < limit;
}
// A prim's box as hashed: clipped to where cloth can query.
inline bool clip(const Aabb& box, const Aabb& bounds, Aabb& out) {
  out.lo = box.lo.cwiseMax(bounds.lo);
  out.hi = box.hi.cwiseMin(bounds.hi);
  return (out.lo.array() <= out.hi.array()).all();
}
}  // namespace spatial_hash_detail

// Hashes every cloth prim (slots [0, c.cloth_prim_count)) by the cells its box s.prim_box covers within
// s.query_bounds, with the model's cell or, when that would take over 64 entries a prim, a larger one
// (s.hash.inv_cell). Grows the entry arrays only when a step needs more entries than any before.
void build_spatial_hash(const CollisionModel& c, CollisionScratch& s);

// Calls visit(slot) once for every prim whose box overlaps q (q within s.query_bounds). A pair found in several
// cells is reported only from the cell holding the low corner of the two boxes' intersection.
template <class Visit>
void query_spatial_hash(const CollisionScratch& s, const Aabb& q, Visit&& visit) {
  using namespace spatial_hash_detail;
  const HashScratch& hs = s.hash;
  // A query beyond the representable cells (a blown-up vertex) would walk up to 2^63 clamped cells: it finds
  // nothing, as the divergence check will stop the run.
  if (hs.table_size == 0 || !within_cell_range(q, hs.inv_cell)) return;
  const Real inv = hs.inv_cell;
  const Cell lo = cell_of(q.lo, inv), hi = cell_of(q.hi, inv);
  for (std::int64_t i = lo.i; i <= hi.i; ++i)
    for (std::int64_t j = lo.j; j <= hi.j; ++j)
      for (std::int64_t k = lo.k; k <= hi.k; ++k) {
        const std::int64_t key = pack(i, j, k);
        const Index b = bucket_of(i, j, k, hs.table_size);
        for (Index e = hs.bucket_offset[b]; e < hs.bucket_offset[b + 1]; ++e) {
          if (hs.entry_cell[e] != key) continue;
          const Index slot = hs.entry_prim[e];
          Aabb box;
          clip(s.prim_box[slot], s.query_bounds, box);
          if (!boxes_overlap(q, box)) continue;
          const Cell ref = cell_of(q.lo.cwiseMax(box.lo), inv);
          if (ref.i == i && ref.j == j && ref.k == k) visit(slot);
        }
      }
}

// The smallest prime >= n (table sizes).
Index next_prime(Index n);

}  // namespace clothsim
