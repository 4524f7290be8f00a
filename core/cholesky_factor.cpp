#include "core/cholesky_factor.h"

#include <dlfcn.h>
#include <suitesparse/cholmod.h>

#include <algorithm>
#include <cstdlib>

#include <Eigen/SparseCore>

#include "core/blas_kernel.h"
#include "core/hinges.h"
#include "core/model.h"

namespace clothsim {

// One connected piece of the particle graph (core/cholesky_factor.h): its own CHOLMOD matrix, factor and solve
// vectors, and its own cholmod_common, so pieces factor and solve on different threads.
struct CholeskyPiece {
  std::vector<Index> particles;  // the piece's particles in its ordering: particles[k] is placed k-th
  std::vector<Index> springs, stitches, hinges;  // whose entries lie in the piece, ascending
  std::vector<int> down_count;   // off-diagonal blocks below the diagonal in each block column
  double flops = 0;              // floating-point operations of one numeric factorisation (the analysis's count)
  cholmod_common common{};
  cholmod_sparse* a = nullptr;  // lower triangle of the permuted matrix (3n x 3n), CHOLMOD's stype -1
  cholmod_factor* factor = nullptr;
  // Right-hand side, solution and cholmod_solve2's workspace, allocated once: a solve allocates nothing.
  cholmod_dense *rhs = nullptr, *sol = nullptr, *work_y = nullptr, *work_e = nullptr;

  CholeskyPiece() { cholmod_start(&common); }
  ~CholeskyPiece() {
    cholmod_free_dense(&rhs, &common);
    cholmod_free_dense(&sol, &common);
    cholmod_free_dense(&work_y, &common);
    cholmod_free_dense(&work_e, &common);
    cholmod_free_factor(&factor, &common);
    cholmod_free_sparse(&a, &common);
    cholmod_finish(&common);
  }
  CholeskyPiece(const CholeskyPiece&) = delete;
  CholeskyPiece& operator=(const CholeskyPiece&) = delete;
};

struct CholeskyFactor {
  std::vector<int> piece_of;    // particle -> its piece
  std::vector<int> new_index;   // particle -> its place in its piece's ordering
  std::vector<int> spring_pos;  // where the spring's block starts among its column's neighbour rows (block_entry)
  std::vector<std::unique_ptr<CholeskyPiece>> pieces;  // the most flops first
};

void CholeskyFactorDelete::operator()(CholeskyFactor* f) const { delete f; }

namespace {

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

// A piece's pattern in the given ordering of its graph (vertex -> its place) and its symbolic factorisation.
std::unique_ptr<CholeskyPiece> analyse(const ParticleGraph& graph, const std::vector<int>& place, bool postorder) {
  auto piece = std::make_unique<CholeskyPiece>();
  const auto n = std::size_t(graph.rows());
  // Each block column J's neighbours K > J, sorted: the order of their rows in every scalar column of J.
  std::vector<std::vector<int>> below(n);
  for (std::size_t a = 0; a < n; ++a)
    for (ParticleGraph::InnerIterator it(graph, Eigen::Index(a)); it; ++it) {
      const int pa = place[a], pb = place[std::size_t(it.row())];
      if (pa < pb) below[std::size_t(pa)].push_back(pb);
    }
  piece->down_count.assign(n, 0);
  std::size_t nnz = 0;
  for (std::size_t j = 0; j < n; ++j) {
    std::sort(below[j].begin(), below[j].end());
    piece->down_count[j] = int(below[j].size());
    nnz += 9 * below[j].size() + 6;
  }
  // The scalar pattern, the lower triangle: column 3J + c holds the diagonal rows 3J+c..3J+2, then rows 3K..3K+2
  // of each neighbour K.
  cholmod_common& c = piece->common;
  const std::size_t dim = 3 * n;
  piece->a = cholmod_allocate_sparse(dim, dim, nnz, /*sorted=*/1, /*packed=*/1, /*stype=*/-1, CHOLMOD_REAL, &c);
  int* outer = static_cast<int*>(piece->a->p);
  int* inner = static_cast<int*>(piece->a->i);
  int at = 0;
  for (std::size_t j = 0; j < n; ++j)
    for (int col = 0; col < 3; ++col) {
      outer[3 * j + std::size_t(col)] = at;
      for (int r = col; r < 3; ++r) inner[at++] = 3 * int(j) + r;
      for (int k : below[j])
        for (int r = 0; r < 3; ++r) inner[at++] = 3 * k + r;
    }
  outer[dim] = at;
  std::fill_n(static_cast<Real*>(piece->a->x), nnz, Real(0));
  // The ordering is the block ordering above (whole 3x3 blocks, so each particle's rows form a supernode
  // together); the supernodal factorisation runs the dense blocks through BLAS (Davis 2006, ch. 9; Chen et al.
  // 2008).
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_NATURAL;
  c.postorder = postorder;
  c.supernodal = CHOLMOD_SUPERNODAL;
  c.final_ll = 1;
  c.print = 0;
  c.error_handler = nullptr;
  piece->factor = cholmod_analyze(piece->a, &c);  // reads the pattern only
  piece->flops = c.fl;
  piece->rhs = cholmod_zeros(dim, 1, CHOLMOD_REAL, &c);
  piece->sol = cholmod_zeros(dim, 1, CHOLMOD_REAL, &c);
  if (!piece->factor || !piece->rhs || !piece->sol) std::abort();  // out of memory while sizing the workspace
  return piece;
}

// Where block row J starts among the neighbours' rows of each scalar column of block column I < J, which the
// pattern holds: those rows are sorted, after the column's diagonal ones.
int block_entry(const CholeskyPiece& piece, int i, int j) {
  const int* outer = static_cast<const int*>(piece.a->p);
  const int* rows = static_cast<const int*>(piece.a->i) + outer[3 * i + 2] + 1;
  return int(std::lower_bound(rows, rows + 3 * piece.down_count[std::size_t(i)], 3 * j) - rows);
}

// The ordering `place` followed by the permutation the analysis of it chose (its postorder), when that keeps each
// particle's three rows together and in order, as a postorder of block columns does; else empty.
std::vector<int> postordered(const CholeskyPiece& piece, const std::vector<int>& place) {
  const int* perm = static_cast<const int*>(piece.factor->Perm);
  const std::size_t dim = piece.factor->n;
  std::vector<int> block_place(dim / 3, 0);  // old place -> new
  for (std::size_t k = 0; k < dim; k += 3) {
    const int old = perm[k];
    if (old % 3 != 0 || perm[k + 1] != old + 1 || perm[k + 2] != old + 2) return {};
    block_place[std::size_t(old / 3)] = int(k / 3);
  }
  std::vector<int> post(place.size(), 0);
  for (std::size_t v = 0; v < place.size(); ++v) post[v] = block_place[std::size_t(place[v])];
  return post;
}

}  // namespace

CholeskyFactorPtr build_cholesky_factor(const Model& m, CholeskyOrdering ordering) {
  blas_on_calling_thread();
  ParticleGraph graph = particle_graph(m);
  CholeskyFactorPtr f(new CholeskyFactor);
  int groups = 0;
  const std::vector<int> group = piece_groups(graph, groups);
  std::vector<std::vector<Index>> members(static_cast<std::size_t>(groups));
  std::vector<int> rank(group.size(), 0);
  for (Index i = 0; i < m.particle_count; ++i) {
    auto& list = members[std::size_t(group[std::size_t(i)])];
    rank[std::size_t(i)] = int(list.size());
    list.push_back(i);
  }
  f->new_index.assign(group.size(), 0);
  std::vector<std::unique_ptr<CholeskyPiece>> pieces;
  for (int g = 0; g < groups; ++g) {
    const std::vector<Index>& list = members[std::size_t(g)];
    ParticleGraph sub = groups == 1 ? std::move(graph) : subgraph(graph, list, rank);
    // Neither ordering wins everywhere: on a plain sheet minimum degree's factor is cheaper (a 64 x 64 grid: 0.46
    // against 0.55 GFlop), on a sewn garment nested dissection's is half (the knife-pleat dress with its 851
    // stitches: 2.3 against 4.7 GFlop; docs/performance.md). The later candidate wins a tie.
    std::unique_ptr<CholeskyPiece> best;
    std::vector<int> best_place;
    for (std::vector<int>& place : candidate_orderings(sub, ordering)) {
      std::unique_ptr<CholeskyPiece> piece = analyse(sub, place, /*postorder=*/true);
      if (!best || piece->flops <= best->flops) {
        best = std::move(piece);
        best_place = std::move(place);
      }
    }
    // CHOLMOD postorders the elimination tree of the ordering it is given, which makes it permute (transpose)
    // the matrix before every factorisation: 3 % of the dress's run, with an allocation each time. The
    // postorder is folded into the ordering instead, and the pattern analysed again in it as it stands.
    if (std::vector<int> post = postordered(*best, best_place); !post.empty()) {
      best = analyse(sub, post, /*postorder=*/false);
      best_place = std::move(post);
    }
    best->particles.assign(list.size(), 0);
    for (std::size_t k = 0; k < list.size(); ++k) {
      f->new_index[std::size_t(list[k])] = best_place[k];
      best->particles[std::size_t(best_place[k])] = list[k];
    }
    pieces.push_back(std::move(best));
  }
  // The most flops first, so that a loop that hands out pieces in order gives the longest ones out first.
  std::stable_sort(pieces.begin(), pieces.end(), [](const auto& a, const auto& b) { return a->flops > b->flops; });
  f->piece_of.assign(group.size(), 0);
  for (std::size_t k = 0; k < pieces.size(); ++k)
    for (Index i : pieces[k]->particles) f->piece_of[std::size_t(i)] = int(k);
  f->pieces = std::move(pieces);
  const auto piece_of = [&](Index particle) -> CholeskyPiece& {
    return *f->pieces[std::size_t(f->piece_of[std::size_t(particle)])];
  };
  f->spring_pos.assign(std::size_t(m.spring_count), 0);
  for (Index s = 0; s < m.spring_count; ++s) {
    CholeskyPiece& piece = piece_of(m.spring_a[s]);
    piece.springs.push_back(s);
    const int pa = f->new_index[std::size_t(m.spring_a[s])], pb = f->new_index[std::size_t(m.spring_b[s])];
    if (pa != pb) f->spring_pos[std::size_t(s)] = block_entry(piece, std::min(pa, pb), std::max(pa, pb));
  }
  for (Index s = 0; s < m.stitch_count; ++s) piece_of(m.stitch_a[s]).stitches.push_back(s);
  for (Index h = 0; h < m.hinge_count; ++h) piece_of(hinge_particles(m, h)[0]).hinges.push_back(h);
  return f;
}

Index cholesky_piece_count(const CholeskyFactor& f) { return Index(f.pieces.size()); }

std::span<const Index> cholesky_piece_particles(const CholeskyFactor& f, Index k) {
  return f.pieces[std::size_t(k)]->particles;
}
std::span<const Index> cholesky_piece_springs(const CholeskyFactor& f, Index k) {
  return f.pieces[std::size_t(k)]->springs;
}
std::span<const Index> cholesky_piece_stitches(const CholeskyFactor& f, Index k) {
  return f.pieces[std::size_t(k)]->stitches;
}
std::span<const Index> cholesky_piece_hinges(const CholeskyFactor& f, Index k) {
  return f.pieces[std::size_t(k)]->hinges;
}

void cholesky_clear_piece(CholeskyFactor& f, Index k) {
  const CholeskyPiece& piece = *f.pieces[std::size_t(k)];
  std::fill_n(static_cast<Real*>(piece.a->x), piece.a->nzmax, Real(0));
}

void cholesky_clear(CholeskyFactor& f) {
  for (Index k = 0; k < cholesky_piece_count(f); ++k) cholesky_clear_piece(f, k);
}

void cholesky_add_diagonal(CholeskyFactor& f, Index particle, const Sym3& block) {
  const CholeskyPiece& piece = *f.pieces[std::size_t(f.piece_of[std::size_t(particle)])];
  const int j = f.new_index[std::size_t(particle)];
  const Mat3 b = block.full();
  Real* v = static_cast<Real*>(piece.a->x);
  const int* outer = static_cast<const int*>(piece.a->p);
  for (int c = 0; c < 3; ++c)
    for (int r = c; r < 3; ++r) v[outer[3 * j + c] + r - c] += b(r, c);
}

namespace {

// Adds sign * block to the off-diagonal block whose rows start `first` entries into the neighbours' rows of each
// scalar column of block column i of particle a's piece (the matrix is symmetric: only the lower of the (a, b) and
// (b, a) blocks is stored).
void add_off_diagonal(CholeskyFactor& f, Index a, int i, int first, const Mat3& block, Real sign) {
  const CholeskyPiece& piece = *f.pieces[std::size_t(f.piece_of[std::size_t(a)])];
  Real* v = static_cast<Real*>(piece.a->x);
  const int* outer = static_cast<const int*>(piece.a->p);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) v[outer[3 * i + c] + 3 - c + first + r] += sign * block(r, c);
}

}  // namespace

void cholesky_add_coupling(CholeskyFactor& f, Index spring, const Sym3& block, Index a, Index b) {
  const int i = std::min(f.new_index[std::size_t(a)], f.new_index[std::size_t(b)]);
  add_off_diagonal(f, a, i, f.spring_pos[std::size_t(spring)], block.full(), -1);
}

void cholesky_add_block(CholeskyFactor& f, Index a, Index b, const Mat3& ab) {
  const int pa = f.new_index[std::size_t(a)], pb = f.new_index[std::size_t(b)];
  const int i = std::min(pa, pb), j = std::max(pa, pb);
  const int first = block_entry(*f.pieces[std::size_t(f.piece_of[std::size_t(a)])], i, j);
  // The stored block has the rows of the particle placed second: A_ab if that is a, else A_ba = ab^T.
  add_off_diagonal(f, a, i, first, pa > pb ? ab : Mat3(ab.transpose()), 1);
}

bool cholesky_factorize_piece(CholeskyFactor& f, Index k) {
  CholeskyPiece& piece = *f.pieces[std::size_t(k)];
  serialise_openmp();
  const int ok = cholmod_factorize(piece.a, piece.factor, &piece.common);
  return ok && piece.common.status == CHOLMOD_OK && piece.factor->minor == piece.factor->n;
}

bool cholesky_factorize(CholeskyFactor& f) {
  bool ok = true;
  for (Index k = 0; k < cholesky_piece_count(f); ++k) ok = cholesky_factorize_piece(f, k) && ok;
  return ok;
}

void cholesky_solve_piece(CholeskyFactor& f, Index k, const Vec3* r, Vec3* z) {
  CholeskyPiece& piece = *f.pieces[std::size_t(k)];
  Real* rhs = static_cast<Real*>(piece.rhs->x);
  for (std::size_t at = 0; at < piece.particles.size(); ++at)
    for (int c = 0; c < 3; ++c) rhs[3 * at + std::size_t(c)] = r[piece.particles[at]][c];
  cholmod_solve2(CHOLMOD_A, piece.factor, piece.rhs, nullptr, &piece.sol, nullptr, &piece.work_y, &piece.work_e,
                 &piece.common);
  const Real* sol = static_cast<const Real*>(piece.sol->x);
  for (std::size_t at = 0; at < piece.particles.size(); ++at)
    z[piece.particles[at]] = Vec3(sol[3 * at], sol[3 * at + 1], sol[3 * at + 2]);
}

void cholesky_solve(CholeskyFactor& f, const Vec3* r, Vec3* z) {
  for (Index k = 0; k < cholesky_piece_count(f); ++k) cholesky_solve_piece(f, k, r, z);
}

double cholesky_piece_flops(const CholeskyFactor& f, Index k) { return f.pieces[std::size_t(k)]->flops; }

double cholesky_flops(const CholeskyFactor& f) {
  double flops = 0;
  for (const auto& piece : f.pieces) flops += piece->flops;
  return flops;
}

std::size_t cholesky_bytes(const CholeskyFactor& f) {
  std::size_t bytes = (f.piece_of.size() + f.new_index.size() + f.spring_pos.size()) * sizeof(int);
  for (const auto& piece : f.pieces) {
    const auto nnz = std::size_t(piece->a->nzmax);
    const std::size_t n = piece->particles.size();
    // A supernodal factor's values (xsize) and row indices (ssize); a simplicial one's nzmax of each.
    const std::size_t values = piece->factor->is_super ? piece->factor->xsize : piece->factor->nzmax;
    const std::size_t rows = piece->factor->is_super ? piece->factor->ssize : piece->factor->nzmax;
    bytes += nnz * (sizeof(Real) + sizeof(int)) + values * sizeof(Real) + rows * sizeof(int) +
             n * (sizeof(Index) + sizeof(int)) + 4 * 3 * n * sizeof(Real) +
             (piece->springs.size() + piece->stitches.size() + piece->hinges.size()) * sizeof(Index);
  }
  return bytes;
}

}  // namespace clothsim
