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
// A matrix of unconnected pieces (a garment's panels before sewing, a scene's separate cloths) is block diagonal:
// each connected piece of the particle graph (small ones gathered into groups of at least 512 particles) gets its
// own ordering and factor, so the pieces factor and solve on different threads, each piece on one, and the bytes
// do not depend on how many threads there are.
#include <memory>
#include <span>
#include <vector>

#include "core/math.h"
#include "core/particle_graph.h"

namespace clothsim {

struct Model;
struct CholeskyFactor;  // CHOLMOD's matrix, factor and solve vectors (core/cholesky_factor.cpp)

struct CholeskyFactorDelete {
  void operator()(CholeskyFactor* f) const;
};
using CholeskyFactorPtr = std::unique_ptr<CholeskyFactor, CholeskyFactorDelete>;

// The lower triangle's pattern (column-major, rows ascending), the ordering and the symbolic factorisation, piece
// by piece.
CholeskyFactorPtr build_cholesky_factor(const Model& model,
                                        CholeskyOrdering ordering = CholeskyOrdering::cheaper);

// The factor's pieces, the most flops first: handed out in that order, the longest start first.
Index cholesky_piece_count(const CholeskyFactor& f);
// What lies in piece k: its particles (in its ordering), and the springs, stitches and hinges whose blocks are in
// its matrix (ascending). Each particle, spring, stitch and hinge is in exactly one piece, so pieces may be filled
// at once on different threads.
std::span<const Index> cholesky_piece_particles(const CholeskyFactor& f, Index k);
std::span<const Index> cholesky_piece_springs(const CholeskyFactor& f, Index k);
std::span<const Index> cholesky_piece_stitches(const CholeskyFactor& f, Index k);
std::span<const Index> cholesky_piece_hinges(const CholeskyFactor& f, Index k);

// The matrix's values, set before factorising: zeroed, then blocks added (values in the original particle order).
void cholesky_clear_piece(CholeskyFactor& f, Index k);
void cholesky_clear(CholeskyFactor& f);  // every piece
void cholesky_add_diagonal(CholeskyFactor& f, Index particle, const Sym3& block);
// Adds -block at (a, b) and (b, a): a spring's coupling (A p)_a = ... - B_s p_b.
void cholesky_add_coupling(CholeskyFactor& f, Index spring, const Sym3& block, Index a, Index b);
// Adds ab at (a, b) and ab^T at (b, a), a != b, for a pair the pattern holds that is not a spring: a stitch's or
// a hinge's particles (found by a search of the column, where a spring's place is precomputed).
void cholesky_add_block(CholeskyFactor& f, Index a, Index b, const Mat3& ab);
// Numeric factorisation of piece k's values; false when its matrix is not positive definite. Pieces may be
// factored at once on different threads; each is factored on one, so the bytes do not depend on the threads.
bool cholesky_factorize_piece(CholeskyFactor& f, Index k);
// All pieces, one after the other; false when any is not positive definite.
bool cholesky_factorize(CholeskyFactor& f);
// z = A^-1 r on piece k's particles with its last factorisation (particle vectors in the original order); pieces
// write disjoint particles of z, so they may be solved at once.
void cholesky_solve_piece(CholeskyFactor& f, Index k, const Vec3* r, Vec3* z);
// All pieces, one after the other.
void cholesky_solve(CholeskyFactor& f, const Vec3* r, Vec3* z);
// Floating-point operations of one numeric factorisation, as CHOLMOD's analysis counts them: of piece k, and of
// all pieces.
double cholesky_piece_flops(const CholeskyFactor& f, Index k);
double cholesky_flops(const CholeskyFactor& f);
// Bytes held: pattern, values, factor and the permuted vectors.
std::size_t cholesky_bytes(const CholeskyFactor& f);

}  // namespace clothsim
