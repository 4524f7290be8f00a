#include "core/topology.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace clothsim {
namespace {

// Open addressing with linear probing over a power-of-two table at most half full: one pass over the
// triangle corners, so the cost is linear in the mesh size (no pairwise triangle comparison). Key and id share a
// slot, and the caller prefetches the slots of triangles a few ahead: a million-triangle mesh's table is far
// larger than the caches, and a probe is otherwise a cache miss.
class EdgeTable {
 public:
  explicit EdgeTable(std::size_t expected) {
    std::size_t cap = 16;
    while (cap < 2 * expected) cap <<= 1;
    slots_.assign(cap, Slot{empty_key, 0});
    mask_ = cap - 1;
  }
  void prefetch(Index a, Index b) const { __builtin_prefetch(&slots_[hash(key(a, b)) & mask_]); }
  // Returns the edge id of (a, b), inserting `next_id` when the pair is new.
  Index find_or_insert(Index a, Index b, Index next_id, bool& inserted) {
    const std::uint64_t k = key(a, b);
    std::size_t slot = hash(k) & mask_;
    while (true) {
      Slot& s = slots_[slot];
      if (s.key == k) { inserted = false; return s.id; }
      if (s.key == empty_key) {
        s = Slot{k, next_id};
        inserted = true;
        return next_id;
      }
      slot = (slot + 1) & mask_;
    }
  }

 private:
  struct Slot {
    std::uint64_t key;
    Index id;
  };
  static constexpr std::uint64_t empty_key = ~std::uint64_t(0);
  static std::uint64_t key(Index a, Index b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); }
  static std::uint64_t hash(std::uint64_t k) {  // splitmix64 finaliser
    k ^= k >> 30; k *= 0xbf58476d1ce4e5b9ULL;
    k ^= k >> 27; k *= 0x94d049bb133111ebULL;
    return k ^ (k >> 31);
  }
  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
};

Index find_root(std::vector<Index>& parent, Index i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

Real twice_triangle_area(const MeshData& mesh, Index t) {
  const Vec3& p0 = mesh.positions[mesh.tri_index[3 * t]];
  const Vec3& p1 = mesh.positions[mesh.tri_index[3 * t + 1]];
  const Vec3& p2 = mesh.positions[mesh.tri_index[3 * t + 2]];
  return (p1 - p0).cross(p2 - p0).norm();
}

Topology build_topology(const MeshData& mesh) {
  Topology topo;
  const Index nt = mesh.triangle_count();
  const Index nv = mesh.vertex_count();
  const std::size_t edges_expected = std::size_t(nt) * 3 / 2 + 1;  // each interior edge has two triangles
  EdgeTable table(edges_expected);
  std::vector<Index> edge_tris;      // triangles sharing each edge
  std::vector<Index> edge_opposite;  // first two opposite vertices of each edge (2 * edge_count)
  topo.edge_a.reserve(edges_expected);
  topo.edge_b.reserve(edges_expected);
  edge_tris.reserve(edges_expected);
  edge_opposite.reserve(2 * edges_expected);
  constexpr Index prefetch_ahead = 8;  // triangles: enough to cover a memory latency

  std::vector<Index> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> used(nv, 0);

  for (Index t = 0; t < nt; ++t) {
    if (t + prefetch_ahead < nt) {
      const Index* p = &mesh.tri_index[3 * std::size_t(t + prefetch_ahead)];
      for (int k = 0; k < 3; ++k) table.prefetch(std::min(p[k], p[(k + 1) % 3]), std::max(p[k], p[(k + 1) % 3]));
    }
    const Index* c = &mesh.tri_index[3 * std::size_t(t)];
    const bool repeated = c[0] == c[1] || c[1] == c[2] || c[0] == c[2];
    if (repeated || twice_triangle_area(mesh, t) <= 0) ++topo.degenerate_triangles;
    for (int k = 0; k < 3; ++k) {
      used[c[k]] = 1;
      const Index a = std::min(c[k], c[(k + 1) % 3]);
      const Index b = std::max(c[k], c[(k + 1) % 3]);
      if (a == b) continue;
      bool inserted = false;
      const Index e = table.find_or_insert(a, b, topo.edge_count(), inserted);
      if (inserted) {
        topo.edge_a.push_back(a);
        topo.edge_b.push_back(b);
        edge_tris.push_back(0);
        edge_opposite.push_back(-1);
        edge_opposite.push_back(-1);
        const Index ra = find_root(parent, a), rb = find_root(parent, b);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
      }
      // A triangle with a repeated corner has no face to share: its edges become springs, but it neither
      // closes a boundary edge nor makes an edge non-manifold (it lists its one real edge twice).
      if (repeated) continue;
      if (edge_tris[e] < 2) edge_opposite[2 * e + edge_tris[e]] = c[(k + 2) % 3];
      ++edge_tris[e];
    }
  }

  topo.bend_a.reserve(topo.edge_count());  // at most one bend pair an edge; untouched capacity costs no memory
  topo.bend_b.reserve(topo.edge_count());
  topo.bend_edge.reserve(topo.edge_count());
  for (Index e = 0; e < topo.edge_count(); ++e) {
    if (edge_tris[e] == 1) ++topo.boundary_edges;
    if (edge_tris[e] >= 3) ++topo.nonmanifold_edges;
    const Index o0 = edge_opposite[2 * e], o1 = edge_opposite[2 * e + 1];
    if (edge_tris[e] == 2 && o0 != o1) {
      topo.bend_a.push_back(std::min(o0, o1));
      topo.bend_b.push_back(std::max(o0, o1));
      topo.bend_edge.push_back(e);
    }
  }
  for (Index i = 0; i < nv; ++i) {
    if (!used[i]) ++topo.unused_vertices;
    else if (find_root(parent, i) == i) ++topo.pieces;
  }
  return topo;
}

}  // namespace clothsim
