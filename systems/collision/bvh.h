#pragma once
// The AABB trees of the broad phase (core/collision_model.h, BvhTree): built once from the topology
// (core/bvh_build.cpp) and refitted when their prims move, level by level from the leaves up.
#include "core/model.h"
#include "systems/collision/proximity.h"

namespace clothsim {

// node_box from the boxes of the tree's slots in prim_box.
void refit_bvh(const BvhTree& tree, const std::vector<Aabb>& prim_box, std::vector<Aabb>& node_box);

// Calls visit(slot) for every slot of the tree whose box overlaps q.
template <class Visit>
void query_bvh(const BvhTree& tree, const std::vector<Aabb>& node_box, const Aabb& q, Visit&& visit) {
  if (tree.node_child.empty() || !boxes_overlap(q, node_box[0])) return;
  // A child is tested before it is pushed, so the stack holds only nodes that meet q; the visits come in the
  // same order as testing each node when popped.
  Index stack[96];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Index n = stack[--top];
    const Index first = tree.node_child[2 * n];
    if (first < 0) {
      visit(~first);
      continue;
    }
    const Index second = tree.node_child[2 * n + 1];
    if (boxes_overlap(q, node_box[first])) stack[top++] = first;
    if (boxes_overlap(q, node_box[second])) stack[top++] = second;
  }
}

}  // namespace clothsim
