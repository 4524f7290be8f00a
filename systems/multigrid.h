#pragma once
// Aggregation multigrid preconditioner for the implicit step's CG (preconditioner="multigrid").
//
// The block-Jacobi preconditioner reaches only a particle's own neighbourhood, while with h^2 k / m >= 1e4 the
// system is a stiffness Laplacian whose smooth modes span the sheet: its CG iterations grow with the sheet's
// width. Here the error is also corrected on coarser levels of aggregates (core/multigrid_levels.h: pairwise
// aggregation after Notay 2010, piecewise-constant prolongation P, Galerkin coarse operators A_c = P^T A P), in a
// symmetric W-cycle: one damped block-Jacobi sweep before and one after each coarse correction, the coarse
// correction scaled by alpha > 1 (a piecewise-constant correction undershoots smooth error; over-correcting plain
// aggregation is an old remedy, e.g. Braess 1995, "Towards algebraic multigrid for elliptic problems of second
// order"), and a dense Cholesky solve on the coarsest level. Each level not solved exactly gets two cycles of the
// level below, the second from the first's result, in place of the K-cycle that Notay pairs with pairwise
// aggregation (two flexible-CG steps per level, Notay & Vassilevski 2008): about the same work, but a fixed linear
// operator, so plain CG applies.
//
// Why CG may use it. With S = I - omega D^-1 A the sweep and C the coarse solve, one cycle's error propagation is
// E = S (I - alpha P C P^T A) S, self-adjoint in the energy inner product, so B = (I - E) A^-1 is symmetric; it is
// positive definite when |E|_A < 1.
// - S contracts: every spring block is positive semi-definite, so p^T A p <= 2 p^T D p (a spring's
//   (p_i - p_j)^T B (p_i - p_j) is at most twice p_i^T B p_i + p_j^T B p_j), the eigenvalues of D^-1 A lie in
//   (0, 2], and those of S in (-1, 1) for 0 < omega < 1.
// - The coarse step I - alpha P C P^T A does not expand when alpha lambda(C A_c) <= 2. An exact C has
//   lambda = 1; two cycles of a coarse B with lambda(B A_c) = mu in (0, 2) give C = 2 B - B A_c B, with
//   lambda(C A_c) = 1 - (1 - mu)^2 in (0, 1]. So with 0 < alpha < 2, by induction from the coarsest level, every
//   level's cycle has |E|_A < 1 and mu in (0, 2). tests/multigrid_test.cpp checks the spectrum densely.
#include <span>

#include "systems/implicit_system.h"

namespace clothsim {

// The levels' numeric blocks for this step: each coarse level's G and B summed from the finer level's (the
// springs' ws.spring_block and the particle blocks on the first), their diagonal inverses, the coarsest factor.
// Needs ws.spring_block and (for the finest smoother) ws.cg_precond current.
void build_multigrid_operators(const Model& model, Real h, Workspace& ws);

// z = B r, one cycle from zero; r and z are particle vectors (zero on pinned particles). Uses ws.cg_q as scratch.
void apply_multigrid(const Model& model, std::span<const Vec3> x, Real h, ImplicitLayout layout, Workspace& ws,
                     std::span<const Vec3> r, std::span<Vec3> z);

}  // namespace clothsim
