#include "core/cholesky_factor.h"

#include <dlfcn.h>
#include <suitesparse/cholmod.h>

#include <algorithm>
#include <cstdlib>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>

#include "core/hinges.h"
#include "core/model.h"

namespace clothsim {

struct CholeskyFactor {
  Index n = 0;                  // particles
  std::vector<int> new_index;   // particle -> its place in the ordering (particle_count)
  std::vector<int> spring_pos;  // the spring's block among the off-diagonal blocks of its column (spring_count)
  std::vector<int> up_count;    // off-diagonal blocks above the diagonal in each block column (particle_count)
  double flops = 0;             // floating-point operations of one numeric factorisation (the analysis's count)
  cholmod_common common{};
  cholmod_sparse* a = nullptr;  // upper triangle of the permuted matrix (3n x 3n), CHOLMOD's stype 1
  cholmod_factor* factor = nullptr;
  // Right-hand side, solution and cholmod_solve2's workspace, allocated once: a solve allocates nothing.
  cholmod_dense *rhs = nullptr, *sol = nullptr, *work_y = nullptr, *work_e = nullptr;

  CholeskyFactor() { cholmod_start(&common); }
  ~CholeskyFactor() {
    cholmod_free_dense(&rhs, &common);
    cholmod_free_dense(&sol, &common);
    cholmod_free_dense(&work_y, &common);
    cholmod_free_dense(&work_e, &common);
    cholmod_free_factor(&factor, &common);
    cholmod_free_sparse(&a, &common);
    cholmod_finish(&common);
  }
  CholeskyFactor(const CholeskyFactor&) = delete;
  CholeskyFactor& operator=(const CholeskyFactor&) = delete;
};

void CholeskyFactorDelete::operator()(CholeskyFactor* f) const { delete f; }

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

using ParticleGraph = Eigen::SparseMatrix<Real, Eigen::ColMajor, int>;

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

// The orderings to analyse for the one asked: nested dissection then minimum degree for the cheaper of the two;
// nested dissection falls back to minimum degree where CHOLMOD has no METIS.
std::vector<std::vector<int>> candidate_orderings(const Model& m, CholeskyOrdering ordering) {
  ParticleGraph graph = particle_graph(m);
  std::vector<std::vector<int>> found;
  if (ordering != CholeskyOrdering::minimum_degree) {
    std::vector<int> nd = nested_dissection(graph);
    if (!nd.empty()) found.push_back(std::move(nd));
  }
  if (ordering != CholeskyOrdering::nested_dissection || found.empty()) found.push_back(minimum_degree(graph));
  return found;
}

// Debian's CHOLMOD runs parts of its supernodal factorisation in OpenMP teams of a fixed 4 threads: on top of
// the step's own threads they cost more than they save (the dress of docs/performance.md: 0.27 s a factorisation
// with them, 0.12 s without, 2.2 s of its 4.6 s run in the kernel). Inactive parallel regions run serially;
// max-active-levels is a per-thread setting, so it is set in the thread that factorises, before each call. Looked
// up at run time so that clothsim links no OpenMP runtime of its own.
void serialise_openmp() {
  using SetLevels = void (*)(int);
  static const auto set_levels = reinterpret_cast<SetLevels>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"));
  if (set_levels) set_levels(0);
}

// The pattern in the given ordering (particle -> its place) and its symbolic factorisation.
CholeskyFactorPtr analyse(const Model& m, std::vector<int> new_index) {
  CholeskyFactorPtr f(new CholeskyFactor);
  const Index n = m.particle_count;
  f->n = n;
  f->new_index = std::move(new_index);

  // Each block column J's neighbours I < J, sorted: the order of their rows in every scalar column of J.
  std::vector<std::vector<int>> above(static_cast<std::size_t>(n));
  for_each_coupled_pair(m, [&](Index a, Index b) {
    const int pa = f->new_index[std::size_t(a)], pb = f->new_index[std::size_t(b)];
    if (pa != pb) above[std::size_t(std::max(pa, pb))].push_back(std::min(pa, pb));
  });
  f->up_count.assign(std::size_t(n), 0);
  std::size_t nnz = 0;
  for (auto& rows : above) {
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  }
  for (Index j = 0; j < n; ++j) {
    f->up_count[std::size_t(j)] = int(above[std::size_t(j)].size());
    nnz += 9 * above[std::size_t(j)].size() + 6;
  }
  f->spring_pos.assign(std::size_t(m.spring_count), 0);
  for (Index s = 0; s < m.spring_count; ++s) {
    const int pa = f->new_index[std::size_t(m.spring_a[s])], pb = f->new_index[std::size_t(m.spring_b[s])];
    const auto& rows = above[std::size_t(std::max(pa, pb))];
    f->spring_pos[std::size_t(s)] = int(std::lower_bound(rows.begin(), rows.end(), std::min(pa, pb)) - rows.begin());
  }
  // The scalar pattern: column 3J + c holds rows 3I..3I+2 of each neighbour I, then the diagonal rows 3J..3J+c.
  cholmod_common& c = f->common;
  const auto dim = std::size_t(3 * n);
  f->a = cholmod_allocate_sparse(dim, dim, nnz, /*sorted=*/1, /*packed=*/1, /*stype=*/1, CHOLMOD_REAL, &c);
  int* outer = static_cast<int*>(f->a->p);
  int* inner = static_cast<int*>(f->a->i);
  int at = 0;
  for (Index j = 0; j < n; ++j)
    for (int col = 0; col < 3; ++col) {
      outer[3 * j + col] = at;
      for (int i : above[std::size_t(j)])
        for (int r = 0; r < 3; ++r) inner[at++] = 3 * i + r;
      for (int r = 0; r <= col; ++r) inner[at++] = 3 * j + r;
    }
  outer[3 * n] = at;
  std::fill_n(static_cast<Real*>(f->a->x), nnz, Real(0));
  // The ordering is the block ordering above (whole 3x3 blocks, so each particle's rows form a supernode
  // together); the supernodal factorisation runs the dense blocks through BLAS (Davis 2006, ch. 9; Chen et al.
  // 2008).
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_NATURAL;
  c.postorder = 1;
  c.supernodal = CHOLMOD_SUPERNODAL;
  c.final_ll = 1;
  c.print = 0;
  c.error_handler = nullptr;
  f->factor = cholmod_analyze(f->a, &c);  // reads the pattern only
  f->flops = c.fl;
  f->rhs = cholmod_zeros(dim, 1, CHOLMOD_REAL, &c);
  f->sol = cholmod_zeros(dim, 1, CHOLMOD_REAL, &c);
  if (!f->factor || !f->rhs || !f->sol) std::abort();  // out of memory while sizing the workspace
  return f;
}

}  // namespace

CholeskyFactorPtr build_cholesky_factor(const Model& m, CholeskyOrdering ordering) {
  // Neither ordering wins everywhere: on a plain sheet minimum degree's factor is cheaper (a 64 x 64 grid: 0.46
  // against 0.55 GFlop), on a sewn garment nested dissection's is half (the knife-pleat dress with its 851
  // stitches: 2.3 against 4.7 GFlop; docs/performance.md). The later candidate wins a tie.
  CholeskyFactorPtr best;
  for (std::vector<int>& new_index : candidate_orderings(m, ordering)) {
    CholeskyFactorPtr f = analyse(m, std::move(new_index));
    if (!best || f->flops <= best->flops) best = std::move(f);
  }
  return best;
}

void cholesky_clear(CholeskyFactor& f) { std::fill_n(static_cast<Real*>(f.a->x), f.a->nzmax, Real(0)); }

void cholesky_add_diagonal(CholeskyFactor& f, Index particle, const Sym3& block) {
  const int j = f.new_index[std::size_t(particle)];
  const Mat3 b = block.full();
  Real* v = static_cast<Real*>(f.a->x);
  const int* outer = static_cast<const int*>(f.a->p);
  for (int c = 0; c < 3; ++c) {
    const int diag = outer[3 * j + c] + 3 * f.up_count[std::size_t(j)];
    for (int r = 0; r <= c; ++r) v[diag + r] += b(r, c);
  }
}

namespace {

// Adds sign * block to the off-diagonal block whose rows start `first` entries into each scalar column of block
// column j (the matrix is symmetric: only the upper of the (a, b) and (b, a) blocks is stored).
void add_off_diagonal(CholeskyFactor& f, int j, int first, const Mat3& block, Real sign) {
  Real* v = static_cast<Real*>(f.a->x);
  const int* outer = static_cast<const int*>(f.a->p);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) v[outer[3 * j + c] + first + r] += sign * block(r, c);
}

}  // namespace

void cholesky_add_coupling(CholeskyFactor& f, Index spring, const Sym3& block, Index a, Index b) {
  const int j = std::max(f.new_index[std::size_t(a)], f.new_index[std::size_t(b)]);
  add_off_diagonal(f, j, 3 * f.spring_pos[std::size_t(spring)], block.full(), -1);
}

void cholesky_add_block(CholeskyFactor& f, Index a, Index b, const Mat3& ab) {
  const int pa = f.new_index[std::size_t(a)], pb = f.new_index[std::size_t(b)];
  const int i = std::min(pa, pb), j = std::max(pa, pb);
  const int* outer = static_cast<const int*>(f.a->p);
  const int* inner = static_cast<const int*>(f.a->i);
  // Block row I's first entry in column 3J: the pattern's rows are sorted, the neighbours' before the diagonal.
  const int* column = inner + outer[3 * j];
  const int first = int(std::lower_bound(column, column + 3 * f.up_count[std::size_t(j)], 3 * i) - column);
  // The stored block has the rows of the particle placed first: A_ab if that is a, else A_ba = ab^T.
  add_off_diagonal(f, j, first, pa < pb ? ab : Mat3(ab.transpose()), 1);
}

bool cholesky_factorize(CholeskyFactor& f) {
  serialise_openmp();
  const int ok = cholmod_factorize(f.a, f.factor, &f.common);
  return ok && f.common.status == CHOLMOD_OK && f.factor->minor == f.factor->n;
}

void cholesky_solve(CholeskyFactor& f, const Vec3* r, Vec3* z) {
  Real* rhs = static_cast<Real*>(f.rhs->x);
  for (Index i = 0; i < f.n; ++i) {
    const std::size_t at = 3 * std::size_t(f.new_index[std::size_t(i)]);
    for (int k = 0; k < 3; ++k) rhs[at + std::size_t(k)] = r[i][k];
  }
  cholmod_solve2(CHOLMOD_A, f.factor, f.rhs, nullptr, &f.sol, nullptr, &f.work_y, &f.work_e, &f.common);
  const Real* sol = static_cast<const Real*>(f.sol->x);
  for (Index i = 0; i < f.n; ++i) {
    const std::size_t at = 3 * std::size_t(f.new_index[std::size_t(i)]);
    z[i] = Vec3(sol[at], sol[at + 1], sol[at + 2]);
  }
}

double cholesky_flops(const CholeskyFactor& f) { return f.flops; }

std::size_t cholesky_bytes(const CholeskyFactor& f) {
  const auto nnz = std::size_t(f.a->nzmax);
  // A supernodal factor's values (xsize) and row indices (ssize); a simplicial one's nzmax of each.
  const std::size_t values = f.factor->is_super ? f.factor->xsize : f.factor->nzmax;
  const std::size_t rows = f.factor->is_super ? f.factor->ssize : f.factor->nzmax;
  return nnz * (sizeof(Real) + sizeof(int)) + values * sizeof(Real) + rows * sizeof(int) +
         (f.new_index.size() + f.spring_pos.size() + f.up_count.size()) * sizeof(int) +
         4 * std::size_t(3 * f.n) * sizeof(Real);
}

}  // namespace clothsim
