#pragma once
// The second broad phase: an AABB tree over the same prims, built once from the topology
// (core/bvh_build.cpp) and refitted every step, level by level from the leaves up.
#include "core/model.h"
#include "systems/collision/proximity.h"

namespace clothsim {

void refit_bvh(const CollisionModel& c, CollisionScratch& s);

// Calls visit(slot) for every prim whose box overlaps q.
template <class Visit>
void query_bvh(const CollisionModel& c, const CollisionScratch& s, const Aabb& q, Visit&& visit) {
  if (c.node_child.empty()) return;
  Index stack[96];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Index n = stack[--top];
    if (!boxes_overlap(q, s.node_box[n])) continue;
    const Index first = c.node_child[2 * n];
    if (first < 0) {
      visit(~first);
    } else {
      stack[top++] = first;
      stack[top++] = c.node_child[2 * n + 1];
    }
  }
}

}  // namespace clothsim
