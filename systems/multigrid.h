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
// Why CG may use it: the cycle B is a fixed linear operator, symmetric (the sweep after the coarse correction is
// the one before it), and positive definite because its error propagation E = S (I - alpha P C P^T A) S contracts
// in the energy norm for 0 < omega < 1 and 0 < alpha < 2 (the proof: docs/stability.md, "Why the multigrid cycle
// is a valid CG preconditioner"). tests/unit/multigrid_test.cpp checks the spectrum densely.
#include <span>

#include "systems/implicit_system.h"

namespace clothsim {

// The levels' numeric blocks for this step: each coarse level's G and B summed from the finer level's (the
// springs' blocks, with_spring_blocks, and the particle blocks on the first), their diagonal inverses, the coarsest
// factor. Needs the spring blocks and (for the finest smoother) ws.cg_precond current.
void build_multigrid_operators(const Model& model, Real h, Workspace& ws);

// z = B r, one cycle from zero; r and z are particle vectors (zero on pinned particles). Uses ws.f as scratch: the
// solve runs after the right-hand side has consumed the forces, and the next force stage overwrites them.
void apply_multigrid(const Model& model, std::span<const Vec3> x, Real h, ImplicitLayout layout, Workspace& ws,
                     std::span<const Vec3> r, std::span<Vec3> z);

}  // namespace clothsim
