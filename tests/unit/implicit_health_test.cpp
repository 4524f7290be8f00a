// The implicit step's health record (SolveRecord) and the sparse Cholesky preconditioner.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "core/memory_bytes.h"
#include "systems/cholesky_preconditioner.h"
#include "systems/integrate_implicit.h"
#include "systems/step.h"
#include "tests/support/scene_fixtures.h"
#include "tests/support/spring_fixtures.h"

using namespace clothsim;
using namespace clothsim::test;

namespace {

// One implicit step; its health is the record it logs, and the StepResult it returns must agree with it.
SolveRecord implicit_step(const BuiltScene& s, const State& in, State& out, Workspace& ws, Real h) {
  const StepResult result = integrate_implicit(s.model, s.options.solver, in, out, ws, h);
  CHECK(result.failed == result.solve.failed());
  return result.solve;
}

BuiltScene stiff_sheet(Preconditioner pc) {
  GridSpec g;
  g.nx = g.ny = 8;
  g.stiffness = 1e5;
  g.damping = 0.1;
  g.pins = {0, 7};
  g.integrator = Integrator::implicit;
  BuiltScene s = grid_sheet(g);
  s.options.solver.preconditioner = pc;
  s.options.solver.cg_tolerance = 1e-6;
  return s;
}

}  // namespace

TEST_CASE("a CG solve stopped at its cap is reported as not converged") {
  BuiltScene s = stiff_sheet(Preconditioner::jacobi);
  s.options.solver.cg_max_iterations = 3;
  Workspace ws = make_workspace(s.model, s.options);
  State out = s.state;
  const SolveRecord r = implicit_step(s, s.state, out, ws, 1.0 / 120);
  CHECK(r.cg_iterations == 3);
  CHECK(r.cg_residual > s.options.solver.cg_tolerance);
  CHECK_FALSE(r.converged);
  CHECK(r.failed());
  s.options.solver.cg_max_iterations = 1000;
  const SolveRecord ok = implicit_step(s, s.state, out, ws, 1.0 / 120);
  CHECK(ok.converged);
  CHECK_FALSE(ok.failed());
}

TEST_CASE("the Cholesky preconditioner solves a step in one CG iteration and keeps its factor while it helps") {
  BuiltScene s = stiff_sheet(Preconditioner::cholesky);
  Workspace ws = make_workspace(s.model, s.options);
  REQUIRE(ws.cholesky);
  const Real h = 1.0 / 120;
  State out = s.state;
  // A fresh factor of the step's own matrix: CG's first iterate is the solution up to round-off.
  SolveRecord r = implicit_step(s, s.state, out, ws, h);
  CHECK(r.factorizations == 1);
  CHECK(r.cg_iterations == 1);
  CHECK(r.cg_residual < 1e-10);
  // The next steps reuse it: a few iterations each, no factorisation unless a solve is not done within
  // cholesky_refactor_iterations.
  int factorizations = 0, iterations = 0;
  for (int k = 0; k < 10; ++k) {
    std::swap(s.state, out);
    r = implicit_step(s, s.state, out, ws, h);
    factorizations += r.factorizations;
    iterations += r.cg_iterations;
    CHECK(r.converged);
  }
  CHECK(factorizations < 10);
  CHECK(iterations >= 10);
  MESSAGE(factorizations << " factorisations and " << iterations << " CG iterations in 10 steps");
  // A new step size refactors.
  r = implicit_step(s, out, s.state, ws, h / 2);
  CHECK(r.factorizations == 1);
  CHECK(r.cg_iterations == 1);
  CHECK(workspace_bytes(ws) > 0);
}

TEST_CASE("the Cholesky-preconditioned implicit run is byte-identical at 1 and 2 threads") {
  State runs[2];
  for (int t = 1; t <= 2; ++t) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
    BuiltScene s = stiff_sheet(Preconditioner::cholesky);
    Workspace ws = make_workspace(s.model, s.options);
    run_steps(s.model, s.options, s.state, ws, 1.0 / 60, 12);
    runs[t - 1] = s.state;
  }
  REQUIRE(runs[0].x.size() == runs[1].x.size());
  CHECK(std::memcmp(runs[0].x.data(), runs[1].x.data(), runs[0].x.size() * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(runs[0].v.data(), runs[1].v.data(), runs[0].v.size() * sizeof(Vec3)) == 0);
}

TEST_CASE("a Cholesky factor stale at its first reuse is renewed before each solve for a run that doubles") {
  BuiltScene s = stiff_sheet(Preconditioner::cholesky);
  Workspace ws = make_workspace(s.model, s.options);
  const Real h = 1.0 / 120;
  // The step's matrix (spring blocks, diagonal) for the factorisations, and a fresh factor used once.
  State out = s.state;
  implicit_step(s, s.state, out, ws, h);
  REQUIRE(ws.cholesky_h == h);
  REQUIRE(ws.cholesky_solves == 1);
  // The bookkeeping of n solves, as solve_cg does it, with whether a kept factor finishes its solve set by hand:
  // factorisations done.
  auto solves = [&](int n, bool kept_factor_finishes) {
    int factorizations = 0;
    for (int k = 0; k < n; ++k) {
      factorizations += refresh_cholesky(s.model, h, ws);
      if (ws.cholesky_solves > 0 && !kept_factor_finishes) factorizations += renew_stale_cholesky(s.model, h, ws);
      ++ws.cholesky_solves;
    }
    return factorizations;
  };
  // Failing its first reuse: renewed at once, then before each of the next 16 solves; then a kept factor is
  // tried again, and each time that fails at once the run doubles, up to 256.
  for (int run : {16, 32, 64, 128, 256, 256}) {
    CAPTURE(run);
    REQUIRE(ws.cholesky_solves == 1);
    CHECK(solves(1, false) == 1);
    CHECK(ws.cholesky_renewal.left == run);
    CHECK(solves(run, false) == run);
    CHECK(ws.cholesky_renewal.left == 0);
  }
  CHECK(cholesky_renew_most == 256);
  // A factor that serves a reuse and fails the next ends the runs: one refactorisation, then reuse.
  CHECK(solves(1, true) == 0);
  CHECK(solves(1, false) == 1);
  CHECK(ws.cholesky_renewal.run == 0);
  CHECK(ws.cholesky_renewal.left == 0);
  CHECK(solves(3, true) == 0);
}

TEST_CASE("a kept Cholesky factor whose CG falls behind the pace to its cap is dropped before the cap") {
  // A stiff sheet spun at 60 rad/s without gravity: each 1/120 s step turns every spring by half a radian, so the
  // first step's factor, which still serves steps 1 and 2, is a poor preconditioner by step 3.
  GridSpec g;
  g.nx = g.ny = 16;
  g.stiffness = 1e7;
  g.damping = 0.1;
  g.gravity = Vec3::Zero();
  g.integrator = Integrator::implicit;
  BuiltScene s = grid_sheet(g);
  for (std::size_t i = 0; i < s.state.x.size(); ++i) s.state.v[i] = Vec3(0, 0, 60).cross(s.state.x[i]);
  s.options.solver.preconditioner = Preconditioner::cholesky;
  s.options.solver.cg_tolerance = 1e-3;
  Workspace ws = make_workspace(s.model, s.options);
  State out = s.state;
  SolveRecord r;
  int factorizations = 0;
  for (int step = 0; step < 4; ++step) {
    r = implicit_step(s, s.state, out, ws, 1.0 / 120);
    factorizations += r.factorizations;
    CHECK(r.converged);
    std::swap(s.state, out);
  }
  // Steps 1 and 2 reuse the first factor; step 3's probe of it falls behind its pace and is restarted with a
  // fresh factor before its cap of 8 iterations (without the pace rule: 8 + 1).
  CHECK(factorizations == 2);
  CHECK(r.factorizations == 1);
  CHECK(r.cg_iterations < cholesky_refactor_iterations);
  CHECK(r.cg_iterations >= 3);  // at least the 2 the pace is judged on, and one with the fresh factor
  MESSAGE("step 3: " << r.cg_iterations << " CG iterations");
}
