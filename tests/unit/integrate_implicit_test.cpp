// GCC 12 with -march=native reports a false -Wmaybe-uninitialized inside Eigen's AVX-512 GEMM packing for the
// dense reference solves of this file; it is Eigen's internals, not this code.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>

#include "systems/diagnostics.h"
#include "systems/forces.h"
#include "systems/integrate_implicit.h"
#include "systems/spring_forces.h"
#include "systems/spring_jacobian.h"
#include "systems/stability.h"
#include "tests/support/dense_system.h"
#include "tests/support/spring_fixtures.h"

using namespace clothsim;
using namespace clothsim::test;

namespace {

// Position of the free end of a pinned-anchor spring (k = 100 N/m, m = 1 kg, omega = 10 rad/s) released from
// 0.1 m of stretch, at t = 1 s, by backward Euler with step h; exact: rest + 0.1 cos(omega t).
Real implicit_error(Real h) {
  BuiltScene s = two_particle_spring(0, 1, 100, 0, 1, 1.1, Integrator::implicit);
  Workspace ws = make_workspace(s.model, s.options);
  run_steps(s.model, s.options, s.state, ws, h, int(std::lround(1.0 / h)));
  return std::abs(s.state.x[1].x() - (1 + 0.1 * std::cos(10.0)));
}

// A grid sheet with damped springs hanging from the two corners of its top row, for the implicit integrator.
BuiltScene damped_implicit_sheet(int nx, int ny, Real cg_tolerance) {
  GridSpec g;
  g.nx = nx;
  g.ny = ny;
  g.damping = 0.3;
  g.pins = {0, nx - 1};
  g.integrator = Integrator::implicit;
  BuiltScene s = grid_sheet(g);
  s.options.solver.cg_tolerance = cg_tolerance;
  return s;
}

// Largest |(out.v - in.v) - dv| over the particles: a step's velocity change against a dense reference's.
Real largest_difference(const State& in, const State& out, const Eigen::VectorXd& dv) {
  Real worst = 0;
  for (std::size_t i = 0; i < in.v.size(); ++i)
    worst = std::max(worst, (out.v[i] - in.v[i] - Vec3(dv.segment<3>(3 * Eigen::Index(i)))).norm());
  return worst;
}

// Textbook preconditioned CG (Shewchuk 1994, B2) on the dense system from y = 0, stopping at |r| <= tol |b|;
// P is applied as the inverse of the 3x3 diagonal blocks of A (block_jacobi) or as the identity. Its iterations.
int dense_pcg_iterations(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, Real tol, bool block_jacobi) {
  const Eigen::Index n = b.size();
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(n, n);
  if (block_jacobi)
    for (Eigen::Index i = 0; i < n; i += 3) P.block<3, 3>(i, i) = A.block<3, 3>(i, i).inverse();
  Eigen::VectorXd r = b, z = P * r, p = z;
  Real rz = r.dot(z);
  int it = 0;
  while (r.norm() > tol * b.norm() && it < 10 * n) {
    const Eigen::VectorXd q = A * p;
    const Real alpha = rz / p.dot(q);
    r -= alpha * q;
    z = P * r;
    const Real rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
    ++it;
  }
  return it;
}

}  // namespace

TEST_CASE("implicit Euler converges at first order on the two-particle spring") {
  const Real e1 = implicit_error(4e-3), e2 = implicit_error(2e-3), e3 = implicit_error(1e-3);
  MESSAGE("errors at h = 4, 2, 1 ms: " << e1 << " " << e2 << " " << e3);
  // First order: halving h halves the error (ratio 2; 4 would be second order).
  CHECK(e1 / e2 == doctest::Approx(2).epsilon(0.1));
  CHECK(e2 / e3 == doctest::Approx(2).epsilon(0.1));
  CHECK(e3 < 0.01);
}

TEST_CASE("one implicit step equals a dense solve of Baraff & Witkin eq. 15-16 on a small sheet") {
  // Block-Jacobi, the multigrid cycle on three levels of aggregates and the sparse Cholesky factor: the
  // preconditioner changes the path, not the solution.
  // Float spring blocks (core/math.h) are tried too: a workspace made at the default tolerance keeps them, and the
  // step is then asked for 1e-13 all the same.
  for (int variant = 0; variant < 5; ++variant) {
    const Preconditioner pc = std::array{Preconditioner::jacobi, Preconditioner::multigrid,
                                         Preconditioner::cholesky}[variant % 3];
    const bool float_blocks = variant >= 3;
    CAPTURE(int(pc));
    CAPTURE(float_blocks);
    BuiltScene s = damped_implicit_sheet(5, 4, 1e-13);
    Model& m = s.model;
    s.options.solver.preconditioner = pc;
    const Index n = m.particle_count;
    // A stretched, moving state, so the transverse terms and the damping Jacobian all matter.
    for (Index i = 0; i < n; ++i) {
      s.state.x[i] *= 1.15;
      s.state.x[i].z() += 0.02 * std::sin(1.7 * i);
      if (m.particle_inv_mass[i] > 0) s.state.v[i] = Vec3(std::sin(0.3 * i), std::cos(0.7 * i), 0.5 * std::sin(i));
    }
    const Real h = 0.02;
    SimOptions made_for = s.options;
    if (float_blocks) made_for.solver.cg_tolerance = kFloatBlockTolerance;
    Workspace ws = make_workspace(m, made_for);
    REQUIRE(ws.spring_block_f32.empty() == !float_blocks);
    if (pc == Preconditioner::multigrid) {
      ws.multigrid = build_multigrid_levels(m, 1);
      REQUIRE(ws.multigrid.levels.size() >= 2);
    }
    State out = s.state;
    const SolveRecord solve = step(m, s.options, s.state, out, ws, h).solve;

    const auto [A, rhs] = dense_system(m, s.state, h);
    const Eigen::VectorXd dv = A.ldlt().solve(rhs);
    // A float block is off by at most float's unit roundoff 2^-24 of itself, so the matrix by that much of each
    // spring's term and the solution by about that much of its size (here 3.7e-9 of it); an error in any term of
    // eq. 15-16 would be of the order of dv itself. With double blocks the solution is the dense one's.
    const double tolerance = float_blocks ? std::ldexp(1.0, -24) : 1e-9;
    CHECK(largest_difference(s.state, out, dv) < tolerance * dv.norm());
    CHECK(dv.norm() > 0.1);  // the step does change the velocities
    for (Index p : m.pinned) CHECK(out.x[p] == s.state.x[p]);
    CHECK(solve.cg_residual <= 1e-13);
    // A fresh sparse factorisation of the step's matrix leaves one CG iteration.
    if (pc == Preconditioner::cholesky) CHECK(solve.cg_iterations == 1);
    else CHECK(solve.cg_iterations > 1);
    MESSAGE("preconditioner " << int(pc) << ": " << solve.cg_iterations << " CG iterations to 1e-13");
  }
}

TEST_CASE("implicit stays bounded on a stiff hanging sheet at 100x the symplectic Euler limit") {
  GridSpec g;
  g.nx = g.ny = 16;
  g.stiffness = 20000;
  g.damping = 0.05;
  g.bend_scale = 0.2;
  g.pins = {0, 15};
  g.integrator = Integrator::implicit;
  BuiltScene s = grid_sheet(g);
  const StableSteps limits = stable_steps(estimate_omega_max(s.model, s.state.x));
  const Real h = 100 * limits.symplectic;
  MESSAGE("omega_max " << limits.omega_max << " rad/s, symplectic limit " << limits.symplectic << " s, h " << h);
  Workspace ws = make_workspace(s.model, s.options);
  const int steps = int(std::ceil(2.0 / h));  // two seconds of swinging and settling
  Real worst_strain = 0;
  State scratch = s.state;
  for (int k = 0; k < steps; ++k) {
    step(s.model, s.options, s.state, scratch, ws, h);
    std::swap(s.state, scratch);
    REQUIRE(state_is_finite(s.state));
    worst_strain = std::max(worst_strain, max_spring_strain(s.model, s.state.x));
  }
  MESSAGE(steps << " steps, largest strain " << worst_strain);
  CHECK(worst_strain < 0.2);
  CHECK(worst_strain > 1e-4);  // it did hang and stretch
  // It sagged: the free bottom corner fell by about the sheet's height (swinging down from the top corners).
  CHECK(s.state.x[g.nx * g.ny - 1].y() < -0.3);

  // The same sheet and step under symplectic Euler explodes within a few steps: the step is really past it.
  BuiltScene sym = grid_sheet(GridSpec{g.nx, g.ny, g.size, g.stiffness, g.damping, g.bend_scale, g.density, 0, g.pins,
                                       g.gravity, Integrator::symplectic});
  Workspace sym_ws = make_workspace(sym.model, sym.options);
  run_steps(sym.model, sym.options, sym.state, sym_ws, h, 10);
  CHECK(!(max_spring_strain(sym.model, sym.state.x) < 1));
}

TEST_CASE("Newton iterations reduce the backward-Euler residual of a step on a strongly nonlinear spring") {
  // Free end swinging sideways at 2 m/s: the spring turns during the step, so one linear solve is inexact.
  auto residual = [](int newton) {
    BuiltScene s = two_particle_spring(0, 0.1, 400, 0, 1, 1.3, Integrator::implicit);
    s.options.solver.newton_iterations = newton;
    s.state.v[1] = Vec3(0, 2, 0);
    Workspace ws = make_workspace(s.model, s.options);
    State out = s.state;
    const Real h = 0.05;
    step(s.model, s.options, s.state, out, ws, h);
    // g(dv) = M dv - h f(x + h (v + dv), v + dv): zero for the exact backward-Euler step.
    const Vec3 f = -spring_force(out.x[0], out.x[1], out.v[0], out.v[1], 1, 400, 0);
    return (0.1 * (out.v[1] - s.state.v[1]) - h * f).norm();
  };
  const Real r1 = residual(1), r2 = residual(2), r4 = residual(4);
  MESSAGE("backward-Euler residual after 1, 2, 4 Newton iterations: " << r1 << " " << r2 << " " << r4);
  CHECK(r1 > 1e-3);
  CHECK(r2 < 0.5 * r1);  // Newton converges quadratically once close: r4 is ~1e-12
  CHECK(r4 < 1e-8);
}

TEST_CASE("CG with the 3x3 block-Jacobi preconditioner takes the iterations of a dense reference PCG") {
  // Masses spread over four decades make the plain CG slow; the block-Jacobi preconditioner must undo that.
  BuiltScene s = damped_implicit_sheet(8, 6, 1e-8);
  Model& m = s.model;
  s.options.solver.preconditioner = Preconditioner::jacobi;
  for (Index i = 0; i < m.particle_count; ++i) {
    if (m.particle_inv_mass[i] > 0) m.particle_inv_mass[i] *= std::pow(1e-4, std::sin(1.3 * i) * 0.5 + 0.5);
    s.state.x[i] *= 1.1;
    s.state.x[i].z() += 0.03 * std::cos(2.1 * i);
  }
  const Real h = 0.02;
  Workspace ws = make_workspace(m, s.options);
  State out = s.state;
  const int ours = step(m, s.options, s.state, out, ws, h).solve.cg_iterations;

  const auto [A, rhs] = dense_system(m, s.state, h);
  const int block_jacobi = dense_pcg_iterations(A, rhs, s.options.solver.cg_tolerance, true);
  const int plain = dense_pcg_iterations(A, rhs, s.options.solver.cg_tolerance, false);
  MESSAGE("CG iterations: clothsim " << ours << ", dense block-Jacobi " << block_jacobi << ", dense plain " << plain);
  CHECK(std::abs(ours - block_jacobi) <= 1);  // the same algorithm, up to round-off at the last iteration
  CHECK(ours < plain / 2);
  const Eigen::VectorXd dv = A.ldlt().solve(rhs);
  CHECK(largest_difference(s.state, out, dv) < 1e-6 * dv.norm());
}
