#pragma once
// Backward Euler after Baraff & Witkin 1998 (eq. 15-16): linearise the forces about the current state and solve
//   (M - h df/dv - h^2 df/dx) dv = h (f + h df/dx v)
// for the velocity change with a preconditioned conjugate gradient (their §5.3, with the constraint filter of §5.3
// for pinned particles: their rows and columns are projected out, S = 0). The preconditioner is block-Jacobi (theirs)
// or an aggregation multigrid cycle (systems/multigrid.h), as the scene's preconditioner says.
#include <span>

#include "core/model.h"
#include "systems/implicit_system.h"
#include "systems/step_result.h"

namespace clothsim {

struct CgResult {
  int iterations = 0;
  Real residual = 0;       // |r| / |b| at exit (0 when b = 0)
  int factorizations = 0;  // Cholesky factorisations done inside the solve (a stale factor renewed)
  Real rhs_norm = 0;       // |b| the residual is measured against
};

// How a solve starts: filtered projects the held particles' normals out of every vector (systems/contact_filter.h);
// a reference |b| > 0 resumes a solve that was cut short (a restart with a fresh preconditioner): CG continues from
// the solution in ws.cg_x, whose residual ws.cg_r holds, and measures that residual against the original |b|
// instead of starting from zero. A probe is a solve with a kept Cholesky factor (systems/cholesky_preconditioner.h):
// it stops early once its pace shows that it will not finish by its cap.
struct CgStart {
  bool filtered = false;
  Real reference = 0;
  bool probe = false;
};

// Advances in by h into out; opt.newton_iterations linear solves (the first is Baraff & Witkin's, later ones are
// Newton corrections of the backward-Euler residual about the latest iterate). Returns the step's health
// (StepResult::solve: CG iterations, residual, convergence) and failed when the solve is not to be trusted
// (SolveRecord::failed: a solve stopped at its cap, or a Newton correction raised the residual). The strain a step
// made is the frame loop's check (sim/frame_stepper.h).
StepResult integrate_implicit(const Model& model, const SolverOptions& opt, const State& in, State& out, Workspace& ws,
                              Real h, ImplicitLayout layout = ImplicitLayout::spring_blocks);

// One preconditioned CG solve of A y = b, b already in ws.cg_r, y left in ws.cg_x; x are the positions the
// springs are linearised about (read by the recompute layout). Builds nothing: the spring blocks, ws.cg_precond
// and (multigrid) the levels' operators must be current. Exposed for the benchmark.
CgResult solve_cg(const Model& model, const SolverOptions& opt, std::span<const Vec3> x, Workspace& ws, Real h,
                  ImplicitLayout layout, CgStart start = {});

}  // namespace clothsim
