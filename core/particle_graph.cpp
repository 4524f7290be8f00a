#include "core/particle_graph.h"

#include <suitesparse/cholmod.h>

#include <array>

#include <Eigen/OrderingMethods>

#include "core/hinges.h"
#include "core/model.h"

namespace clothsim {

namespace {

// Calls pair(a, b) for each pair of particles the matrix couples: the ends of every spring, each two distinct
// particles of a stitch (the vertex and the two it is sewn between), so a seam between panels is in the pattern,
// and each two of a dihedral hinge's four (o1-o2 is no spring's: it replaces the bend spring there).
template <class Pair>
void for_each_coupled_pair(const Model& m, Pair&& pair) {
  for (Index s = 0; s < m.spring_count; ++s) pair(m.spring_a[s], m.spring_b[s]);
  for (Index s = 0; s < m.stitch_count; ++s) {
    const Index p[3] = {m.stitch_a[s], m.stitch_b[s], m.stitch_c[s]};
    for (int k = 0; k < 3; ++k)
      for (int l = k + 1; l < 3; ++l)
        if (p[k] != p[l]) pair(p[k], p[l]);
  }
  for (Index h = 0; h < m.hinge_count; ++h) {
    const std::array<Index, 4> p = hinge_particles(m, h);
    for (int k = 0; k < 4; ++k)
      for (int l = k + 1; l < 4; ++l) pair(p[k], p[l]);
  }
}

// Particle -> its place, from old_of_new[k], the particle placed k-th.
std::vector<int> places(const int* old_of_new, Index n) {
  std::vector<int> new_index(std::size_t(n), 0);
  for (Index k = 0; k < n; ++k) new_index[std::size_t(old_of_new[k])] = k;
  return new_index;
}

// METIS's nested dissection (Karypis & Kumar 1998, through CHOLMOD) of the graph, read as its upper triangle:
// particle -> its place. METIS seeds its own generator with a fixed value, so the ordering is the same on every
// run and at any thread count. Empty where CHOLMOD was built without METIS.
std::vector<int> nested_dissection(ParticleGraph& graph) {
  cholmod_sparse a{};
  a.nrow = a.ncol = std::size_t(graph.rows());
  a.nzmax = std::size_t(graph.nonZeros());
  a.p = graph.outerIndexPtr();
  a.i = graph.innerIndexPtr();
  a.x = graph.valuePtr();
  a.stype = 1;  // symmetric, upper triangle read
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_PATTERN;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  c.error_handler = nullptr;
  std::vector<int> old_of_new(std::size_t(graph.rows()), 0);
  const bool ok = cholmod_metis(&a, nullptr, 0, /*postorder=*/1, old_of_new.data(), &c) && c.status == CHOLMOD_OK;
  cholmod_finish(&c);
  return ok ? places(old_of_new.data(), graph.rows()) : std::vector<int>{};
}

// Approximate minimum degree (Amestoy, Davis & Duff 1996) of the graph: particle -> its place.
std::vector<int> minimum_degree(const ParticleGraph& graph) {
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> old_of_new;  // AMD returns the inverse permutation
  Eigen::AMDOrdering<int>()(graph, old_of_new);
  return places(old_of_new.indices().data(), graph.rows());
}

}  // namespace

// The particles and the pairs for_each_coupled_pair names, as a symmetric pattern (both triangles, compressed).
ParticleGraph particle_graph(const Model& m) {
  const Index n = m.particle_count;
  std::vector<Eigen::Triplet<Real, int>> entries;
  entries.reserve(std::size_t(n) + 2 * std::size_t(m.spring_count));
  for (Index i = 0; i < n; ++i) entries.emplace_back(i, i, 1);
  for_each_coupled_pair(m, [&](Index a, Index b) {
    entries.emplace_back(a, b, 1);
    entries.emplace_back(b, a, 1);
  });
  ParticleGraph graph(n, n);
  graph.setFromTriplets(entries.begin(), entries.end());
  graph.makeCompressed();
  return graph;
}

// The orderings to analyse for the one asked: nested dissection then minimum degree for the cheaper of the two;
// nested dissection falls back to minimum degree where CHOLMOD has no METIS.
std::vector<std::vector<int>> candidate_orderings(ParticleGraph& graph, CholeskyOrdering ordering) {
  std::vector<std::vector<int>> found;
  if (ordering != CholeskyOrdering::minimum_degree) {
    std::vector<int> nd = nested_dissection(graph);
    if (!nd.empty()) found.push_back(std::move(nd));
  }
  if (ordering != CholeskyOrdering::nested_dissection || found.empty()) found.push_back(minimum_degree(graph));
  return found;
}

std::vector<int> piece_groups(const ParticleGraph& graph, int& group_count) {
  const Index n = Index(graph.rows());
  std::vector<int> piece(std::size_t(n), -1);
  std::vector<Index> size, stack;
  for (Index seed = 0; seed < n; ++seed) {
    if (piece[std::size_t(seed)] >= 0) continue;
    const int id = int(size.size());
    size.push_back(0);
    piece[std::size_t(seed)] = id;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const Index a = stack.back();
      stack.pop_back();
      ++size.back();
      for (ParticleGraph::InnerIterator it(graph, a); it; ++it)
        if (piece[std::size_t(it.row())] < 0) {
          piece[std::size_t(it.row())] = id;
          stack.push_back(Index(it.row()));
        }
    }
  }
  std::vector<int> group_of(size.size(), 0);
  group_count = 0;
  int small_group = -1;  // the group small pieces join, while it holds fewer than piece_group_particles
  Index small_size = 0;
  for (std::size_t k = 0; k < size.size(); ++k) {
    if (size[k] >= piece_group_particles) {
      group_of[k] = group_count++;
      continue;
    }
    if (small_group < 0) {
      small_group = group_count++;
      small_size = 0;
    }
    group_of[k] = small_group;
    small_size += size[k];
    if (small_size >= piece_group_particles) small_group = -1;
  }
  for (int& p : piece) p = group_of[std::size_t(p)];
  return piece;
}

// The graph of the given particles (ascending), numbered by their rank.
ParticleGraph subgraph(const ParticleGraph& graph, const std::vector<Index>& members, const std::vector<int>& rank) {
  std::vector<Eigen::Triplet<Real, int>> entries;
  for (std::size_t k = 0; k < members.size(); ++k)
    for (ParticleGraph::InnerIterator it(graph, members[k]); it; ++it)
      entries.emplace_back(rank[std::size_t(it.row())], int(k), 1);
  ParticleGraph sub(Eigen::Index(members.size()), Eigen::Index(members.size()));
  sub.setFromTriplets(entries.begin(), entries.end());
  sub.makeCompressed();
  return sub;
}

}  // namespace clothsim
