#pragma once
// The sparse Cholesky preconditioner of the implicit step's CG (preconditioner="cholesky"; core/cholesky_factor.h).
//
// Slivers and stiff springs leave the matrix ill-conditioned in ways that neither block-Jacobi nor aggregation
// multigrid sees (a sliver's short edge is a stiffness outlier local to one particle pair, not a smooth mode),
// while an exact factorisation does not care: with a fresh factor CG converges in one iteration. The
// factorisation is the expensive part, so it is kept while it still preconditions well: the matrix changes
// slowly from step to step (the spring directions turn), and CG with the factor of a nearby matrix converges in
// a few iterations. It is refactored numerically when the step size changes, and a solve with a kept factor
// that has not converged after cholesky_refactor_iterations, or falls behind the pace to converge by then, is
// restarted with a fresh one (the restart's iterations count too), so a stale factor costs a few iterations,
// never a failed solve. A very stiff cloth's factor can go stale within one step (on the knife-pleat dress at
// 1/120 s a one-step-old factor needs 35 to 90 iterations, a fresh one 1): when a factor fails its first reuse,
// it is renewed before each of the next cholesky_renew_first solves, a run that doubles each time that recurs
// (up to cholesky_renew_most) and ends once a factor serves a reuse. The rules read iteration counts and
// residuals only, never clocks, so the same scene makes the same choices at any thread count.
#include <span>

#include "core/model.h"

namespace clothsim {

// CG iterations a kept factor gets before its solve restarts with a fresh one. It restarts sooner, from the
// second iteration on, once the rate its residual fell at so far, kept up to that cap, would leave it more than
// cholesky_probe_margin times the tolerance (on the knife-pleat dress a one-step-old factor's residual is still
// 0.78 or 0.40 after two iterations: eight would leave 0.36 or 0.024 of it, at a tolerance of 1e-3).
inline constexpr int cholesky_refactor_iterations = 8;
inline constexpr Real cholesky_probe_margin = 10;
// The first and the longest run of solves that each get a fresh factor.
inline constexpr int cholesky_renew_first = 16;
inline constexpr int cholesky_renew_most = 256;

// Refactors before a solve when due (no factor for this step size, or a renewal run); ws.spring_block_f64 and
// ws.cg_precond (the inverse diagonal blocks) must be current. Returns the number of numeric factorisations
// done (0 or 1). A failed factorisation (the matrix not positive definite
// in floating point) leaves no factor: the solve then falls back to block-Jacobi.
int refresh_cholesky(const Model& model, Real h, Workspace& ws);

// Refactors after a kept factor failed to finish a solve, and starts or ends a renewal run. Returns 1.
int renew_stale_cholesky(const Model& model, Real h, Workspace& ws);

// Drops the kept factor: the next solve factors afresh (the symbolic analysis stays). Every frame starts so
// (sim/simulation.cpp). A checkpoint holds no factor, so a run resumed from one could not otherwise precondition
// its first steps as the whole run did, and would write other bytes. A renewal run goes on (ws.cholesky_renewal,
// which the checkpoint holds): in one, the first solve of a frame refactors anyway.
void forget_cholesky_factor(Workspace& ws);

// z = B r: the factor's solve, or block-Jacobi while there is no valid factor.
void apply_cholesky(const Model& model, Workspace& ws, std::span<const Vec3> r, std::span<Vec3> z);

}  // namespace clothsim
