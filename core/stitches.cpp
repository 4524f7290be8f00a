#include "core/stitches.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include "core/model.h"

namespace clothsim {
namespace {

Index find_root(std::vector<Index>& parent, Index i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Connected piece of every vertex (its union-find root over the triangles) and whether it lies on a boundary
// edge (an edge of one triangle).
void pieces_and_boundary(const MeshData& mesh, std::vector<Index>& piece, std::vector<char>& boundary) {
  const Index n = mesh.vertex_count();
  piece.resize(n);
  std::iota(piece.begin(), piece.end(), 0);
  std::vector<std::pair<Index, Index>> edges;
  edges.reserve(mesh.tri_index.size());
  for (Index t = 0; t < mesh.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Index a = mesh.tri_index[3 * t + k], b = mesh.tri_index[3 * t + (k + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b));
      piece[find_root(piece, a)] = find_root(piece, b);
    }
  for (Index i = 0; i < n; ++i) piece[i] = find_root(piece, i);
  std::sort(edges.begin(), edges.end());
  boundary.assign(n, 0);
  for (std::size_t e = 0; e < edges.size();) {
    std::size_t f = e;
    while (f < edges.size() && edges[f] == edges[e]) ++f;
    if (f - e == 1) boundary[edges[e].first] = boundary[edges[e].second] = 1;
    e = f;
  }
}

}  // namespace

void add_weld_stitches(const MeshData& mesh, std::span<const Vec3> x, Real distance, StitchList& out) {
  if (!(distance > 0)) return;
  std::vector<Index> piece;
  std::vector<char> boundary;
  pieces_and_boundary(mesh, piece, boundary);
  // Boundary vertices sorted by x: each looks at those within distance along x only.
  std::vector<Index> order;
  for (Index i = 0; i < mesh.vertex_count(); ++i)
    if (boundary[i]) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return x[a].x() < x[b].x() || (x[a].x() == x[b].x() && a < b); });
  std::vector<std::pair<Index, Index>> pairs;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const Index i = order[k];
    Index best = -1;
    Real best_d2 = distance * distance;
    auto visit = [&](std::size_t q) {
      const Index j = order[q];
      const Real d2 = (x[j] - x[i]).squaredNorm();
      if (piece[j] != piece[i] && (d2 < best_d2 || (d2 == best_d2 && (best < 0 || j < best)))) {
        best = j;
        best_d2 = d2;
      }
    };
    for (std::size_t q = k + 1; q < order.size() && x[order[q]].x() - x[i].x() <= distance; ++q) visit(q);
    for (std::size_t q = k; q-- > 0 && x[i].x() - x[order[q]].x() <= distance;) visit(q);
    if (best >= 0) pairs.emplace_back(std::min(i, best), std::max(i, best));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  for (const auto& [i, j] : pairs) out.add(i, j, j, 0);
}

void append_stitches(Model& m, const StitchList& s, Index base, std::span<const Vec3> x, const ParamField& stiffness,
                     const ParamField& damping, Real sew_speed) {
  for (std::size_t k = 0; k < s.a.size(); ++k) {
    const Index a = base + s.a[k], b = base + s.b[k], c = base + s.c[k];
    const Real w = s.w[k];
    const Vec3 gap = x[a] - ((1 - w) * x[b] + w * x[c]);
    m.stitch_a.push_back(a);
    m.stitch_b.push_back(b);
    m.stitch_c.push_back(c);
    m.stitch_w.push_back(w);
    m.stitch_ke.push_back(stiffness[s.a[k]]);
    m.stitch_kd.push_back(damping[s.a[k]]);
    m.stitch_gap0.push_back(gap);
    m.stitch_close_time.push_back(gap.norm() / sew_speed);
  }
  m.stitch_count = Index(m.stitch_a.size());
}

void build_particle_stitches(Model& m) {
  m.particle_stitch_offset.assign(std::size_t(m.particle_count) + 1, 0);
  const Index* ends[3] = {m.stitch_a.data(), m.stitch_b.data(), m.stitch_c.data()};
  for (Index s = 0; s < m.stitch_count; ++s)
    for (int k = 0; k < 3; ++k) ++m.particle_stitch_offset[ends[k][s] + 1];
  for (Index i = 0; i < m.particle_count; ++i) m.particle_stitch_offset[i + 1] += m.particle_stitch_offset[i];
  m.particle_stitch_index.assign(std::size_t(3) * m.stitch_count, 0);
  std::vector<Index> next(m.particle_stitch_offset.begin(), m.particle_stitch_offset.end() - 1);
  for (Index s = 0; s < m.stitch_count; ++s)
    for (int k = 0; k < 3; ++k) m.particle_stitch_index[next[ends[k][s]]++] = 3 * s + k;
}

}  // namespace clothsim
