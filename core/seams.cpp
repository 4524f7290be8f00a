#include "core/seams.h"

#include <algorithm>
#include <limits>
#include <tuple>
#include <utility>
#include <vector>

namespace clothsim {
namespace {

// The point a stitch sews its vertex to, when that point is one of the two vertices (w = 0 or 1, or b = c), or -1.
Index coincident_partner(const Model& m, Index s) {
  if (m.stitch_w[s] == 0 || m.stitch_b[s] == m.stitch_c[s]) return m.stitch_b[s];
  if (m.stitch_w[s] == 1) return m.stitch_c[s];
  return -1;
}

Index group_root(std::vector<Index>& parent, Index i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// The sewn rows, (particle, neighbour) in both orders, with repeats. Vertices sewn to coincide (a stitch with
// w = 0 or 1), directly or through a chain of such stitches, are one point of the garment: where three or four
// panels meet, a vertex is sewn to a second, which is sewn to a third, and the first and third touch as closely
// as the first two. So each particle's row lists its group (the chains' union) and the groups of the particles
// any member is stitched to (a, b and c of a stitch).
std::vector<std::pair<Index, Index>> sewn_rows(const Model& m) {
  std::vector<Index> parent(std::size_t(m.particle_count));
  for (Index i = 0; i < m.particle_count; ++i) parent[i] = i;
  for (Index s = 0; s < m.stitch_count; ++s) {
    const Index o = coincident_partner(m, s);
    if (o >= 0) parent[group_root(parent, m.stitch_a[s])] = group_root(parent, o);
  }
  // The members of each group, by root: the stitched particles only.
  std::vector<std::pair<Index, Index>> member;  // (root, particle)
  std::vector<std::pair<Index, Index>> links;   // (particle, stitched partner), both ways
  for (Index s = 0; s < m.stitch_count; ++s)
    for (const Index o : {m.stitch_b[s], m.stitch_c[s]}) {
      links.emplace_back(m.stitch_a[s], o);
      links.emplace_back(o, m.stitch_a[s]);
    }
  for (const auto& [i, o] : links) member.emplace_back(group_root(parent, i), i);
  std::sort(member.begin(), member.end());
  member.erase(std::unique(member.begin(), member.end()), member.end());
  auto group_of = [&](Index i) {
    const Index r = group_root(parent, i);
    const auto lo = std::lower_bound(member.begin(), member.end(), std::make_pair(r, Index(-1)));
    auto hi = lo;
    while (hi != member.end() && hi->first == r) ++hi;
    return std::make_pair(lo, hi);
  };
  std::vector<std::pair<Index, Index>> rows;
  for (const auto& [u, o] : links) {  // every member of u's group to every member of its partner's
    const auto [ulo, uhi] = group_of(u);
    const auto [olo, ohi] = group_of(o);
    for (auto i = ulo; i != uhi; ++i)
      for (auto j = olo; j != ohi; ++j) rows.emplace_back(i->second, j->second);
  }
  for (auto lo = member.begin(); lo != member.end();) {  // the members of a group to each other
    auto hi = lo;
    while (hi != member.end() && hi->first == lo->first) ++hi;
    for (auto i = lo; i != hi; ++i)
      for (auto j = lo; j != hi; ++j) rows.emplace_back(i->second, j->second);
    lo = hi;
  }
  return rows;
}

// The cloth's triangle edges as a graph, each edge weighted by its spring's rest length (a rest mesh's, when
// the cloth has one): the in-plane distances, whichever bending model adds its own springs or none.
struct RestGraph {
  std::vector<Index> offset, to;
  std::vector<Real> length;
};
RestGraph rest_graph(const Model& m) {
  std::vector<std::tuple<Index, Index, Real>> rest;  // (low, high, rest length) of every spring
  for (Index s = 0; s < m.spring_count; ++s)
    rest.emplace_back(std::min(m.spring_a[s], m.spring_b[s]), std::max(m.spring_a[s], m.spring_b[s]), m.spring_rest[s]);
  std::sort(rest.begin(), rest.end());
  std::vector<std::tuple<Index, Index, Real>> arcs;  // both ways
  for (Index t = 0; t < m.tri_count; ++t)
    for (int k = 0; k < 3; ++k) {
      const Index p = m.tri_index[3 * t + k], q = m.tri_index[3 * t + (k + 1) % 3];
      const Index lo_end = std::min(p, q), hi_end = std::max(p, q);
      const auto lo = std::lower_bound(rest.begin(), rest.end(), std::make_tuple(lo_end, hi_end, Real(0)));
      if (lo == rest.end() || std::get<0>(*lo) != lo_end || std::get<1>(*lo) != hi_end) continue;
      arcs.emplace_back(p, q, std::get<2>(*lo));
      arcs.emplace_back(q, p, std::get<2>(*lo));
    }
  std::sort(arcs.begin(), arcs.end());
  arcs.erase(std::unique(arcs.begin(), arcs.end()), arcs.end());
  RestGraph g;
  g.offset.assign(std::size_t(m.particle_count) + 1, 0);
  for (const auto& [p, q, l] : arcs) {
    ++g.offset[p + 1];
    g.to.push_back(q);
    g.length.push_back(l);
  }
  for (Index i = 0; i < m.particle_count; ++i) g.offset[i + 1] += g.offset[i];
  return g;
}

// The particles within `reach` of particle i along the rest graph, with their distances (a bounded Dijkstra).
// dist holds +inf for every particle on entry and on return.
void rest_ball(const RestGraph& g, Index i, Real reach, std::vector<Real>& dist,
               std::vector<std::pair<Index, Real>>& ball) {
  ball.clear();
  std::vector<std::pair<Real, Index>> heap{{Real(0), i}};
  dist[i] = 0;
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), std::greater<>());
    const auto [d, p] = heap.back();
    heap.pop_back();
    if (d > dist[p]) continue;
    ball.emplace_back(p, d);
    for (Index k = g.offset[p]; k < g.offset[p + 1]; ++k) {
      const Index q = g.to[k];
      const Real dq = d + g.length[k];
      if (dq <= reach && dq < dist[q]) {
        dist[q] = dq;
        heap.emplace_back(dq, q);
        std::push_heap(heap.begin(), heap.end(), std::greater<>());
      }
    }
  }
  for (const auto& [p, d] : ball) dist[p] = std::numeric_limits<Real>::infinity();
}

}  // namespace

// The seam CSR, each row sorted, without repeats or the particle itself. Besides the sewn rows, particles u and
// v are neighbours when a sewn pair (i, j) lies between them at rest: the rest distance u..i plus j..v, along the
// triangle edges, within seam_reach_thicknesses of the larger thickness of i and j. Where a seam folds its panels
// face to face (a pleat, a side seam pulled round a body), the cloth next to the seam cannot be held a thickness
// from the other panel without holding the seam open (docs/garments.md). Paths through the mesh alone add
// nothing: a plain fold keeps its contacts.
void build_seams(const Model& m, CollisionModel& c) {
  std::vector<std::pair<Index, Index>> rows = sewn_rows(m);
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  const RestGraph graph = rest_graph(m);
  std::vector<Real> dist(std::size_t(m.particle_count), std::numeric_limits<Real>::infinity());
  std::vector<std::pair<Index, Real>> ball_i, ball_j;
  const std::size_t sewn = rows.size();
  for (std::size_t r = 0; r < sewn; ++r) {
    const auto [i, j] = rows[r];
    if (i >= j) continue;  // rows hold both orders; the pairs below are added both ways
    const Real reach =
        seam_reach_thicknesses * std::max(m.particle_thickness[std::size_t(i)], m.particle_thickness[std::size_t(j)]);
    rest_ball(graph, i, reach, dist, ball_i);
    rest_ball(graph, j, reach, dist, ball_j);
    for (const auto& [u, du] : ball_i)
      for (const auto& [v, dv] : ball_j)
        if (du + dv <= reach && u != v) {
          rows.emplace_back(u, v);
          rows.emplace_back(v, u);
        }
  }
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  c.seam_offset.assign(std::size_t(m.particle_count) + 1, 0);
  c.seam_index.clear();
  for (const auto& [i, j] : rows) {
    if (i == j) continue;
    ++c.seam_offset[i + 1];
    c.seam_index.push_back(j);
  }
  for (Index i = 0; i < m.particle_count; ++i) c.seam_offset[i + 1] += c.seam_offset[i];
}

}  // namespace clothsim
