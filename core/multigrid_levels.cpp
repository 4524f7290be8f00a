#include "core/multigrid_levels.h"

#include <algorithm>
#include <numeric>

#include "core/model.h"

namespace clothsim {
namespace {

// A level's edges under a parent map: one per pair of distinct parents that some finer edge joins, in the order
// (lower parent, higher parent), with the finer edges summed into each as a CSR in index order; finer edges
// with exactly one end without a parent (a pinned particle) are listed under the other end's parent (ground).
struct MergedEdges {
  std::vector<Index> a, b;
  std::vector<Index> source_offset, source_index;
  std::vector<Index> ground_offset, ground_index;
};

MergedEdges merge_edges(const std::vector<Index>& finer_a, const std::vector<Index>& finer_b,
                        const std::vector<Index>& parent, Index node_count) {
  const Index finer_edges = Index(finer_a.size());
  MergedEdges out;
  // Counting sort of the finer edges by their lower parent (and of the ground edges by their one parent).
  std::vector<Index> bucket_offset(std::size_t(node_count) + 1, 0);
  out.ground_offset.assign(std::size_t(node_count) + 1, 0);
  auto ends = [&](Index e) { return std::pair{parent[finer_a[e]], parent[finer_b[e]]}; };
  for (Index e = 0; e < finer_edges; ++e) {
    const auto [p, q] = ends(e);
    if (p < 0 && q < 0) continue;
    if (p < 0 || q < 0) ++out.ground_offset[std::max(p, q) + 1];
    else if (p != q) ++bucket_offset[std::min(p, q) + 1];
  }
  std::partial_sum(bucket_offset.begin(), bucket_offset.end(), bucket_offset.begin());
  std::partial_sum(out.ground_offset.begin(), out.ground_offset.end(), out.ground_offset.begin());
  std::vector<Index> bucket(std::size_t(bucket_offset.back()));
  out.ground_index.resize(std::size_t(out.ground_offset.back()));
  {
    std::vector<Index> fill(bucket_offset.begin(), bucket_offset.end() - 1);
    std::vector<Index> ground_fill(out.ground_offset.begin(), out.ground_offset.end() - 1);
    for (Index e = 0; e < finer_edges; ++e) {
      const auto [p, q] = ends(e);
      if (p < 0 && q < 0) continue;
      if (p < 0 || q < 0) out.ground_index[ground_fill[std::max(p, q)]++] = e;
      else if (p != q) bucket[fill[std::min(p, q)]++] = e;
    }
  }
  // Within a bucket, by higher parent then finer edge index; each run of one higher parent is one edge.
  out.source_offset.push_back(0);
  out.source_index.reserve(bucket.size());
  for (Index lo = 0; lo < node_count; ++lo) {
    const auto first = bucket.begin() + bucket_offset[lo], last = bucket.begin() + bucket_offset[lo + 1];
    auto higher = [&](Index e) { return std::max(parent[finer_a[e]], parent[finer_b[e]]); };
    std::sort(first, last, [&](Index e, Index f) { return std::pair{higher(e), e} < std::pair{higher(f), f}; });
    for (auto it = first; it != last; ++it) {
      if (it != first && higher(*it) != higher(*(it - 1))) out.source_offset.push_back(Index(out.source_index.size()));
      if (it == first || higher(*it) != higher(*(it - 1))) {
        out.a.push_back(lo);
        out.b.push_back(higher(*it));
      }
      out.source_index.push_back(*it);
    }
    if (first != last) out.source_offset.push_back(Index(out.source_index.size()));
  }
  return out;
}

// Pairwise matching (after Notay 2010, with the strength of a connection taken from the stiffness at rest instead of
// the matrix entries, so the aggregates do not depend on the state): each unmatched node, in index order, joins
// its unmatched neighbour of largest weight (the lower index on a tie), or stays alone. Nodes with parent_in < 0
// take no part. Returns each node's pair, -1 for the nodes left out; `count` receives the number of pairs.
std::vector<Index> match_pairs(Index n, const std::vector<Index>& a, const std::vector<Index>& b,
                               const std::vector<Real>& w, const std::vector<char>& active, Index& count) {
  std::vector<Index> offset(std::size_t(n) + 1, 0), neighbour(2 * a.size());
  std::vector<Real> weight(2 * a.size());
  for (std::size_t e = 0; e < a.size(); ++e) {
    ++offset[a[e] + 1];
    ++offset[b[e] + 1];
  }
  std::partial_sum(offset.begin(), offset.end(), offset.begin());
  {
    std::vector<Index> fill(offset.begin(), offset.end() - 1);
    for (std::size_t e = 0; e < a.size(); ++e) {
      neighbour[fill[a[e]]] = b[e];
      weight[fill[a[e]]++] = w[e];
      neighbour[fill[b[e]]] = a[e];
      weight[fill[b[e]]++] = w[e];
    }
  }
  std::vector<Index> pair(std::size_t(n), -1);
  count = 0;
  for (Index i = 0; i < n; ++i) {
    if (!active[i] || pair[i] >= 0) continue;
    Index best = -1;
    Real best_w = 0;
    for (Index k = offset[i]; k < offset[i + 1]; ++k) {
      const Index j = neighbour[k];
      if (!active[j] || pair[j] >= 0) continue;
      if (weight[k] > best_w || (weight[k] == best_w && best >= 0 && j < best)) {
        best = j;
        best_w = weight[k];
      }
    }
    pair[i] = count;
    if (best >= 0) pair[best] = count;
    ++count;
  }
  return pair;
}

// Sum of the finer weights of each merged edge.
std::vector<Real> merged_weights(const MergedEdges& m, const std::vector<Real>& finer_w) {
  std::vector<Real> w(m.a.size(), 0.0);
  for (std::size_t e = 0; e < m.a.size(); ++e)
    for (Index k = m.source_offset[e]; k < m.source_offset[e + 1]; ++k) w[e] += finer_w[m.source_index[k]];
  return w;
}

// The rows of a level's operator: each node's neighbours across its edges (ends a, b), in edge order.
void build_rows(MultigridLevel& level, const std::vector<Index>& a, const std::vector<Index>& b) {
  level.row_offset.assign(std::size_t(level.node_count) + 1, 0);
  for (Index e = 0; e < level.edge_count; ++e) {
    ++level.row_offset[a[e] + 1];
    ++level.row_offset[b[e] + 1];
  }
  std::partial_sum(level.row_offset.begin(), level.row_offset.end(), level.row_offset.begin());
  level.row_col.resize(2 * std::size_t(level.edge_count));
  level.row_edge.resize(2 * std::size_t(level.edge_count));
  std::vector<Index> fill(level.row_offset.begin(), level.row_offset.end() - 1);
  for (Index e = 0; e < level.edge_count; ++e) {
    const Index ka = fill[a[e]]++, kb = fill[b[e]]++;
    level.row_col[ka] = b[e];
    level.row_col[kb] = a[e];
    level.row_edge[ka] = level.row_edge[kb] = e;
  }
}

// Members of each aggregate, in index order.
void build_members(MultigridLevel& level) {
  level.member_offset.assign(std::size_t(level.node_count) + 1, 0);
  for (Index p : level.parent)
    if (p >= 0) ++level.member_offset[p + 1];
  std::partial_sum(level.member_offset.begin(), level.member_offset.end(), level.member_offset.begin());
  level.member_index.resize(std::size_t(level.member_offset.back()));
  std::vector<Index> fill(level.member_offset.begin(), level.member_offset.end() - 1);
  for (Index i = 0; i < Index(level.parent.size()); ++i)
    if (level.parent[i] >= 0) level.member_index[fill[level.parent[i]]++] = i;
}

}  // namespace

Multigrid build_multigrid_levels(const Model& m, Index coarsest_nodes) {
  constexpr double stall_ratio = 0.75;  // two pairwise rounds leave about a quarter of the nodes
  Multigrid mg;
  // The finer level of the first coarse level: particles, pinned ones left out, springs weighted by stiffness.
  Index finer_nodes = m.particle_count;
  std::vector<Index> finer_a = m.spring_a, finer_b = m.spring_b;
  std::vector<Real> finer_w(std::size_t(m.spring_count));
  for (Index s = 0; s < m.spring_count; ++s) finer_w[s] = m.spring_ke[s];
  std::vector<Index> identity(static_cast<std::size_t>(finer_nodes));  // finer node -> itself, -1 when left out (pinned)
  Index free_count = 0;
  for (Index i = 0; i < finer_nodes; ++i) {
    identity[i] = m.particle_inv_mass[i] > 0 ? i : -1;
    free_count += identity[i] >= 0;
  }

  while (free_count > 0) {
    // Two rounds of pairwise matching on the graph of the finer level (unique pairs, summed weights).
    MergedEdges graph = merge_edges(finer_a, finer_b, identity, finer_nodes);
    std::vector<Real> graph_w = merged_weights(graph, finer_w);
    std::vector<char> active(static_cast<std::size_t>(finer_nodes));
    for (Index i = 0; i < finer_nodes; ++i) active[i] = identity[i] >= 0;
    Index pairs = 0;
    const std::vector<Index> first = match_pairs(finer_nodes, graph.a, graph.b, graph_w, active, pairs);
    MergedEdges pair_graph = merge_edges(graph.a, graph.b, first, pairs);
    Index quads = 0;
    const std::vector<Index> second =
        match_pairs(pairs, pair_graph.a, pair_graph.b, merged_weights(pair_graph, graph_w),
                    std::vector<char>(std::size_t(pairs), 1), quads);
    if (quads > stall_ratio * free_count && !mg.levels.empty()) break;
    if (quads == free_count) break;  // no spring joins two free nodes: nothing to aggregate

    MultigridLevel level;
    level.node_count = quads;
    level.parent.resize(std::size_t(finer_nodes));
    for (Index i = 0; i < finer_nodes; ++i) level.parent[i] = first[i] < 0 ? -1 : second[first[i]];
    MergedEdges edges = merge_edges(finer_a, finer_b, level.parent, quads);
    level.edge_count = Index(edges.a.size());
    // The cycle reads the edges through the rows; their two ends are kept only to build the next level.
    build_rows(level, edges.a, edges.b);
    finer_w = merged_weights(edges, finer_w);
    finer_a = std::move(edges.a);
    finer_b = std::move(edges.b);
    level.source_offset = std::move(edges.source_offset);
    level.source_index = std::move(edges.source_index);
    if (mg.levels.empty()) {  // only the springs to pinned particles ground a node
      level.ground_offset = std::move(edges.ground_offset);
      level.ground_index = std::move(edges.ground_index);
    }
    // Held for the whole run: no spare capacity from push_back growth.
    for (auto* v : {&level.source_offset, &level.source_index}) v->shrink_to_fit();
    build_members(level);
    for (auto* v : {&level.diag, &level.diag_inv}) v->assign(std::size_t(quads), Sym3{});
    level.edge_block.assign(std::size_t(level.edge_count), Sym3f{});
    for (auto* v : {&level.b, &level.x, &level.t}) v->assign(std::size_t(quads), Vec3::Zero());

    // This level is the next one's finer level.
    finer_nodes = free_count = quads;
    identity.resize(std::size_t(quads));
    std::iota(identity.begin(), identity.end(), 0);
    mg.levels.push_back(std::move(level));
    if (quads <= coarsest_nodes) break;
  }
  if (!mg.levels.empty() && mg.levels.back().node_count <= multigrid_dense_max_nodes) {
    const Index n = 3 * mg.levels.back().node_count;
    mg.dense_coarsest = true;
    mg.dense.setZero(n, n);
    mg.dense_factor.setZero(n, n);
    mg.dense_rhs.setZero(n);
  }
  return mg;
}

}  // namespace clothsim
