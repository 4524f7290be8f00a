#include <algorithm>
#include <numeric>

#include "core/build_collision.h"

namespace clothsim {

// A binary AABB tree over slots first_slot + [0, centroid count), one slot a leaf, built once from the initial
// centroids (median split on the longest axis) and stored breadth first, so a refit can update one level at a time in
// parallel, deepest level first (systems/collision/bvh.cpp).
void build_bvh_topology(const std::vector<Vec3>& centroid, Index first_slot, BvhTree& c) {
  struct Range { Index begin, end; };
  std::vector<Index> order(centroid.size());
  std::iota(order.begin(), order.end(), 0);
  c.node_child.clear();
  c.level_offset.assign(1, 0);
  if (order.empty()) { c.level_offset.push_back(0); return; }
  std::vector<Range> level{{0, Index(order.size())}}, next;
  while (!level.empty()) {
    next.clear();
    const Index first_child = Index(c.node_child.size() / 2 + level.size());
    for (const Range& r : level) {
      if (r.end - r.begin == 1) {
        c.node_child.push_back(~(first_slot + order[r.begin]));  // leaf: ~slot in CollisionModel::prim
        c.node_child.push_back(-1);
        continue;
      }
      Vec3 lo = centroid[order[r.begin]], hi = lo;
      for (Index k = r.begin; k < r.end; ++k) {
        lo = lo.cwiseMin(centroid[order[k]]);
        hi = hi.cwiseMax(centroid[order[k]]);
      }
      int axis = 0;
      (hi - lo).maxCoeff(&axis);
      const Index mid = (r.begin + r.end) / 2;
      std::nth_element(order.begin() + r.begin, order.begin() + mid, order.begin() + r.end, [&](Index a, Index b) {
        return centroid[a][axis] < centroid[b][axis] || (centroid[a][axis] == centroid[b][axis] && a < b);
      });
      const Index child = first_child + Index(next.size());
      c.node_child.push_back(child);
      c.node_child.push_back(child + 1);
      next.push_back({r.begin, mid});
      next.push_back({mid, r.end});
    }
    c.level_offset.push_back(Index(c.node_child.size() / 2));
    std::swap(level, next);
  }
}

}  // namespace clothsim
