#include "systems/collision/candidate_cache.h"

#include "systems/collision/broad_phase.h"

namespace clothsim {
namespace {

// One kind's lists: each element's query box from box(e), grown by `grow`, walked through the cloth tree (when
// `cloth`) and the colliders' tree, keeping the slots that may_pair(e, slot) allows (a slot it refuses could give
// the walks no pair, whatever the positions). The blocks are fixed, so the lists are the same at any thread count.
template <class Box, class MayPair>
void make_lists(const Model& m, const CollisionScratch& s, Index elements, bool cloth, Real grow, Box&& box,
                MayPair&& may_pair, CandidateLists& lists) {
  const CollisionModel& c = m.collision;
  lists.block.resize(std::size_t((elements + candidate_block - 1) / candidate_block));
  lists.end.resize(std::size_t(elements));
  parallel_over(Index(lists.block.size()), 1, [&](Index b) {
    std::vector<Index>& kept = lists.block[std::size_t(b)];
    kept.clear();
    Index e = 0;
    const auto keep = [&](Index slot) {
      if (may_pair(e, slot)) kept.push_back(slot);
    };
    for (e = b * candidate_block; e < std::min(elements, (b + 1) * candidate_block); ++e) {
      Aabb q = box(e);
      q.lo.array() -= grow;
      q.hi.array() += grow;
      if (cloth) query_bvh(c.cloth_tree, s.cloth_node_box, q, keep);
      query_bvh(c.collider_tree, s.collider_node_box, q, keep);
      lists.end[std::size_t(e)] = Index(kept.size());
    }
  });
}

}  // namespace

void make_candidate_lists(const Model& m, const State& in, const State& out, CollisionScratch& s) {
  const CollisionModel& c = m.collision;
  CandidateCache& k = s.candidates;
  k.on = false;
  if (c.broad_phase != BroadPhase::bvh || c.prim.empty()) return;
  k.margin = candidate_margin_thicknesses * c.max_thickness;
  const Real grow = 2 * k.margin;
  const auto any_slot = [](Index, Index) { return true; };
  // The edge walk (for_each_edge_pair) takes from a cloth triangle only its paired edges, so an edge keeps only
  // the cloth slots that hold one.
  const auto edge_may_pair = [&](Index e, Index slot) {
    const Index prim = c.prim[slot];
    if (prim >= m.tri_count) return true;
    bool any = false;
    for_each_paired_edge(c, e, prim, [&](Index) { any = true; });
    return any;
  };
  make_lists(m, s, m.particle_count, true, grow, [&](Index i) { return vertex_query(in, out, i); }, any_slot,
             k.vertex);
  make_lists(m, s, Index(c.edge_a.size()), true, grow, [&](Index e) { return edge_query(c, in, out, e); },
             edge_may_pair, k.edge);
  make_lists(m, s, m.tri_count, false, grow, [&](Index t) { return triangle_query(m, in, out, t); }, any_slot,
             k.triangle);
  k.x_ref = out.x;
  k.in_ref = in.x.data();
  k.runaway.clear();
  k.is_runaway.assign(std::size_t(c.cloth_prim_count), 0);
  k.on = true;
}

void note_cloth_boxes(const Model& m, const State& in, const State& out, CollisionScratch& s) {
  CandidateCache& k = s.candidates;
  if (!k.on) return;
  if (in.x.data() != k.in_ref) {
    k.on = false;
    return;
  }
  const CollisionModel& c = m.collision;
  // Slots in ascending order, serially: the few that run away are found in a pass over flags.
  parallel_over(c.cloth_prim_count, 1024, [&](Index slot) {
    const Index* p = &m.tri_index[3 * c.prim[slot]];
    k.is_runaway[std::size_t(slot)] = !near_lists(k, out, p, 3);
  });
  k.runaway.clear();
  for (Index slot = 0; slot < c.cloth_prim_count; ++slot)
    if (k.is_runaway[std::size_t(slot)]) k.runaway.push_back(slot);
}

const CandidateLists* usable_candidates(const State& in, const CollisionScratch& s, WalkKind kind) {
  const CandidateCache& k = s.candidates;
  if (!k.on || in.x.data() != k.in_ref || k.runaway.size() > runaway_limit) return nullptr;
  return kind == WalkKind::vertex ? &k.vertex : kind == WalkKind::edge ? &k.edge : &k.triangle;
}

}  // namespace clothsim
