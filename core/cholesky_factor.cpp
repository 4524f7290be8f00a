#include "core/cholesky_factor.h"

#include <algorithm>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/model.h"

namespace clothsim {

using SparseMat = Eigen::SparseMatrix<Real, Eigen::ColMajor, int>;

struct CholeskyFactor {
  Index n = 0;                  // particles
  std::vector<int> new_index;   // particle -> its place in the ordering (particle_count)
  std::vector<int> spring_pos;  // the spring's block among the off-diagonal blocks of its column (spring_count)
  std::vector<int> up_count;    // off-diagonal blocks above the diagonal in each block column (particle_count)
  SparseMat a;                  // upper triangle of the permuted matrix (3n x 3n)
  // Upper: with the natural ordering Eigen factors the input in place, without a permuted copy.
  Eigen::SimplicialLDLT<SparseMat, Eigen::Upper, Eigen::NaturalOrdering<int>> ldlt;
  Eigen::VectorXd rhs, sol;     // permuted right-hand side and solution (3n)
};

void CholeskyFactorDelete::operator()(CholeskyFactor* f) const { delete f; }

CholeskyFactorPtr build_cholesky_factor(const Model& m) {
  CholeskyFactorPtr f(new CholeskyFactor);
  const Index n = m.particle_count;
  f->n = n;
  // Particle graph, both triangles, for the ordering.
  std::vector<Eigen::Triplet<Real, int>> entries;
  entries.reserve(std::size_t(n) + 2 * std::size_t(m.spring_count));
  for (Index i = 0; i < n; ++i) entries.emplace_back(i, i, 1);
  for (Index s = 0; s < m.spring_count; ++s) {
    entries.emplace_back(m.spring_a[s], m.spring_b[s], 1);
    entries.emplace_back(m.spring_b[s], m.spring_a[s], 1);
  }
  SparseMat graph(n, n);
  graph.setFromTriplets(entries.begin(), entries.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> old_of_new;  // AMD returns the inverse permutation
  Eigen::AMDOrdering<int>()(graph, old_of_new);
  f->new_index.assign(std::size_t(n), 0);
  for (Index k = 0; k < n; ++k) f->new_index[std::size_t(old_of_new.indices()[k])] = k;

  // Each block column J's neighbours I < J, sorted: the order of their rows in every scalar column of J.
  std::vector<std::vector<int>> above(static_cast<std::size_t>(n));
  for (Index s = 0; s < m.spring_count; ++s) {
    const int pa = f->new_index[std::size_t(m.spring_a[s])], pb = f->new_index[std::size_t(m.spring_b[s])];
    if (pa != pb) above[std::size_t(std::max(pa, pb))].push_back(std::min(pa, pb));
  }
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
  f->a.resize(3 * n, 3 * n);
  f->a.resizeNonZeros(Eigen::Index(nnz));
  int* outer = f->a.outerIndexPtr();
  int* inner = f->a.innerIndexPtr();
  int at = 0;
  for (Index j = 0; j < n; ++j)
    for (int c = 0; c < 3; ++c) {
      outer[3 * j + c] = at;
      for (int i : above[std::size_t(j)])
        for (int r = 0; r < 3; ++r) inner[at++] = 3 * i + r;
      for (int r = 0; r <= c; ++r) inner[at++] = 3 * j + r;
    }
  outer[3 * n] = at;
  std::fill_n(f->a.valuePtr(), nnz, Real(0));
  for (Index j = 0; j < n; ++j) f->a.coeffRef(3 * j, 3 * j) = 1;  // any SPD values: the analysis reads the pattern
  f->ldlt.analyzePattern(f->a);
  f->rhs.setZero(3 * n);
  f->sol.setZero(3 * n);
  return f;
}

void cholesky_clear(CholeskyFactor& f) { std::fill_n(f.a.valuePtr(), f.a.nonZeros(), Real(0)); }

void cholesky_add_diagonal(CholeskyFactor& f, Index particle, const Sym3& block) {
  const int j = f.new_index[std::size_t(particle)];
  const Mat3 b = block.full();
  Real* v = f.a.valuePtr();
  const int* outer = f.a.outerIndexPtr();
  for (int c = 0; c < 3; ++c) {
    const int diag = outer[3 * j + c] + 3 * f.up_count[std::size_t(j)];
    for (int r = 0; r <= c; ++r) v[diag + r] += b(r, c);
  }
}

void cholesky_add_coupling(CholeskyFactor& f, Index spring, const Sym3& block, Index a, Index b) {
  const int pa = f.new_index[std::size_t(a)], pb = f.new_index[std::size_t(b)];
  const int j = std::max(pa, pb), first = 3 * f.spring_pos[std::size_t(spring)];
  const Mat3 m = block.full();  // symmetric, so the (a, b) and (b, a) blocks are the same
  Real* v = f.a.valuePtr();
  const int* outer = f.a.outerIndexPtr();
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) v[outer[3 * j + c] + first + r] -= m(r, c);
}

bool cholesky_factorize(CholeskyFactor& f) {
  f.ldlt.factorize(f.a);
  return f.ldlt.info() == Eigen::Success && (f.ldlt.vectorD().array() > 0).all();
}

void cholesky_solve(CholeskyFactor& f, const Vec3* r, Vec3* z) {
  for (Index i = 0; i < f.n; ++i) f.rhs.segment<3>(3 * f.new_index[std::size_t(i)]) = r[i];
  f.sol = f.ldlt.solve(f.rhs);
  for (Index i = 0; i < f.n; ++i) z[i] = f.sol.segment<3>(3 * f.new_index[std::size_t(i)]);
}

std::size_t cholesky_bytes(const CholeskyFactor& f) {
  const auto nnz = std::size_t(f.a.nonZeros());
  const auto factor = std::size_t(f.ldlt.matrixL().nestedExpression().nonZeros());
  return (nnz + factor) * (sizeof(Real) + sizeof(int)) +
         (f.new_index.size() + f.spring_pos.size() + f.up_count.size()) * sizeof(int) +
         std::size_t(f.rhs.size() + f.sol.size() + f.ldlt.vectorD().size()) * sizeof(Real);
}

}  // namespace clothsim
