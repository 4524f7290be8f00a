#pragma once
// The sparse Cholesky factorisation of the implicit step's matrix (preconditioner="cholesky"): the matrix's
// pattern is fixed for the run (one 3x3 block per particle, per spring, per pair of a stitch's particles and per
// pair of a hinge's), so the fill-reducing ordering and
// the symbolic factorisation are computed once when the workspace is made, and each refactorisation is numeric
// only (Davis 2006, "Direct Methods for Sparse Linear Systems", ch. 4 and 7). The ordering is the cheaper, by the
// analysis's flop count, of METIS's nested dissection and approximate minimum degree of the particle graph, applied
// to whole 3x3 blocks, so a block's three rows stay adjacent and each spring's block lands in one contiguous run of
// every column it touches.
// CHOLMOD's supernodal LL^T (Chen, Davis, Hager & Rajamanickam 2008) factors it: the dense blocks of columns
// with the same pattern go through BLAS. On the knife-pleat dress (47k unknowns, 4.8 M entries in L with AMD)
// it factors 2.7x and solves 1.7x faster than Eigen's simplicial LDL^T did (docs/performance.md).
#include <memory>
#include <vector>

#include "core/math.h"

namespace clothsim {

struct Model;
struct CholeskyFactor;  // CHOLMOD's matrix, factor and solve vectors (core/cholesky_factor.cpp)

struct CholeskyFactorDelete {
  void operator()(CholeskyFactor* f) const;
};
using CholeskyFactorPtr = std::unique_ptr<CholeskyFactor, CholeskyFactorDelete>;

// Fill-reducing orderings of the particle graph: the cheaper of the two that follow, nested dissection (METIS
// through CHOLMOD, approximate minimum degree where CHOLMOD has no METIS), or approximate minimum degree (Eigen's).
enum class CholeskyOrdering { cheaper, nested_dissection, minimum_degree };

// The upper triangle's pattern (column-major, rows ascending), the ordering and the symbolic factorisation.
CholeskyFactorPtr build_cholesky_factor(const Model& model,
                                        CholeskyOrdering ordering = CholeskyOrdering::cheaper);

// The matrix's values, set before factorising: zeroed, then blocks added (values in the original particle order).
void cholesky_clear(CholeskyFactor& f);
void cholesky_add_diagonal(CholeskyFactor& f, Index particle, const Sym3& block);
// Adds -block at (a, b) and (b, a): a spring's coupling (A p)_a = ... - B_s p_b.
void cholesky_add_coupling(CholeskyFactor& f, Index spring, const Sym3& block, Index a, Index b);
// Adds ab at (a, b) and ab^T at (b, a), a != b, for a pair the pattern holds that is not a spring: a stitch's or
// a hinge's particles (found by a search of the column, where a spring's place is precomputed).
void cholesky_add_block(CholeskyFactor& f, Index a, Index b, const Mat3& ab);
// Numeric factorisation of the values set; false when the matrix is not positive definite.
// Single-threaded: the same bytes at any thread count.
bool cholesky_factorize(CholeskyFactor& f);
// z = A^-1 r with the last factorisation (particle vectors in the original order).
void cholesky_solve(CholeskyFactor& f, const Vec3* r, Vec3* z);
// Floating-point operations of one numeric factorisation, as CHOLMOD's analysis counts them.
double cholesky_flops(const CholeskyFactor& f);
// Bytes held: pattern, values, factor and the permuted vectors.
std::size_t cholesky_bytes(const CholeskyFactor& f);

}  // namespace clothsim
