#include "systems/collision/bvh.h"

#include "systems/parallel.h"

namespace clothsim {

void refit_bvh(const BvhTree& c, const std::vector<Aabb>& prim_box, std::vector<Aabb>& node_box) {
  const Index levels = Index(c.level_offset.size()) - 1;
  for (Index l = levels - 1; l >= 0; --l) {
    const Index begin = c.level_offset[l], end = c.level_offset[l + 1];
    parallel_over(end - begin, 1024, [&](Index k) {
      const Index n = begin + k;
      const Index a = c.node_child[2 * n];
      if (a < 0) {
        node_box[n] = prim_box[~a];
      } else {
        const Aabb& l0 = node_box[a];
        const Aabb& l1 = node_box[c.node_child[2 * n + 1]];
        node_box[n].lo = l0.lo.cwiseMin(l1.lo);
        node_box[n].hi = l0.hi.cwiseMax(l1.hi);
      }
    });
  }
}

}  // namespace clothsim
