// GCC 12 with -march=native reports a false -Wmaybe-uninitialized inside Eigen's AVX-512 GEMM packing for the
// dense reference solves of this file; it is Eigen's internals, not this code.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "systems/diagnostics.h"
#include "systems/spring_jacobian.h"
#include "systems/stability.h"
#include "tests/support/spring_fixtures.h"

using namespace clothsim;
using namespace clothsim::test;

namespace {

// Dense reference: largest generalised eigenvalue of K u = lambda M u over the free particles, K = -df/dx at rest.
Real dense_omega_max(const Model& m, const std::vector<Vec3>& x) {
  std::vector<Index> slot(m.particle_count, -1);
  Index free = 0;
  for (Index i = 0; i < m.particle_count; ++i)
    if (m.particle_inv_mass[i] > 0) slot[i] = free++;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * free, 3 * free), M = K;
  for (Index i = 0; i < m.particle_count; ++i)
    if (slot[i] >= 0) M.block<3, 3>(3 * slot[i], 3 * slot[i]) = Mat3::Identity() / m.particle_inv_mass[i];
  for (Index s = 0; s < m.spring_count; ++s) {
    const Index a = m.spring_a[s], b = m.spring_b[s];
    const Mat3 k = spring_jacobian(x[a], x[b], m.spring_rest[s], m.spring_ke[s], 0).dfdx;
    if (slot[a] >= 0) K.block<3, 3>(3 * slot[a], 3 * slot[a]) += k;
    if (slot[b] >= 0) K.block<3, 3>(3 * slot[b], 3 * slot[b]) += k;
    if (slot[a] >= 0 && slot[b] >= 0) {
      K.block<3, 3>(3 * slot[a], 3 * slot[b]) -= k;
      K.block<3, 3>(3 * slot[b], 3 * slot[a]) -= k;
    }
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, M, Eigen::EigenvaluesOnly);
  return std::sqrt(eig.eigenvalues().maxCoeff());
}

// Energy of the undamped spring (kinetic + potential) after each of `steps` steps.
std::vector<Real> energies(BuiltScene s, Real h, int steps) {
  Workspace ws = make_workspace(s.model, s.options);
  std::vector<Real> e;
  State scratch = s.state;
  for (int k = 0; k < steps; ++k) {
    step(s.model, s.options, s.state, scratch, ws, h);
    std::swap(s.state, scratch);
    e.push_back(mechanical_energy(s.model, s.state, s.state.x));  // no gravity: the reference does not matter
  }
  return e;
}

}  // namespace

TEST_CASE("omega_max of the two-particle spring: power iteration, closed form and dense solve agree") {
  // Two free masses 1 and 3 kg on k = 120 N/m: omega^2 = k (1/m1 + 1/m2) = 160.
  BuiltScene s = two_particle_spring(1, 3, 120, 0, 1, 1, Integrator::symplectic);
  const Real est = estimate_omega_max(s.model, s.state.x);
  CHECK(est == doctest::Approx(std::sqrt(160.0)).epsilon(1e-6));
  CHECK(dense_omega_max(s.model, s.state.x) == doctest::Approx(std::sqrt(160.0)).epsilon(1e-9));
  const StableSteps l = stable_steps(est);
  CHECK(l.symplectic == doctest::Approx(2 / std::sqrt(160.0)).epsilon(1e-6));
  CHECK(l.rk4 == doctest::Approx(2 * std::sqrt(2.0) / std::sqrt(160.0)).epsilon(1e-6));
  CHECK(stable_step_limit(l, Integrator::euler) == 0);
  CHECK(std::isinf(stable_step_limit(l, Integrator::implicit)));
}

TEST_CASE("omega_max of a pinned 7x6 grid is within 5% of the dense generalised eigen-solve") {
  GridSpec g;
  g.nx = 7;
  g.ny = 6;
  g.stiffness = 800;
  g.bend_scale = 0.3;
  g.pins = {0, 6};
  BuiltScene s = grid_sheet(g);
  const Real est = estimate_omega_max(s.model, s.state.x), exact = dense_omega_max(s.model, s.state.x);
  MESSAGE("power iteration " << est << " rad/s, dense " << exact << " rad/s");
  CHECK(est == doctest::Approx(exact).epsilon(0.05));
  CHECK(est <= exact * (1 + 1e-9));  // a Rayleigh quotient never exceeds lambda_max
}

TEST_CASE("the symplectic Euler limit 2/omega_max is where the undamped spring turns unstable") {
  // Anchor pinned, free mass 0.5 kg, k = 50 N/m: omega = 10 rad/s, limit 0.2 s.
  auto grows = [](Real h) {
    BuiltScene s = two_particle_spring(0, 0.5, 50, 0, 1, 1.05, Integrator::symplectic);
    const std::vector<Real> e = energies(s, h, 2000);
    return e.back() / e.front();
  };
  const Real limit = stable_steps(estimate_omega_max(two_particle_spring(0, 0.5, 50, 0, 1, 1, Integrator::symplectic).model,
                                                     std::vector<Vec3>{Vec3(0, 0, 0), Vec3(1, 0, 0)})).symplectic;
  CHECK(limit == doctest::Approx(0.2).epsilon(1e-6));
  CHECK(grows(0.97 * limit) < 10);
  CHECK(!(grows(1.03 * limit) < 1e6));
}

TEST_CASE("undamped spring energy: symplectic keeps it, implicit loses it every step, explicit Euler gains it") {
  // Anchor pinned, free mass 1 kg, k = 100 N/m (omega 10, period 0.628 s), released from 5 cm of stretch.
  auto spring = [](Integrator integ) { return two_particle_spring(0, 1, 100, 0, 1, 1.05, integ); };
  const Real period = 2 * std::numbers::pi / 10;
  const Real e0 = 0.5 * 100 * 0.05 * 0.05;

  // Symplectic Euler at h omega = 0.05 (1/40 of its limit 0.2 s), over 1000 periods: the energy oscillates by
  // about h omega / 2 (it conserves a nearby modified energy exactly) and does not drift.
  const Real h_sym = 0.005;
  const std::vector<Real> sym = energies(spring(Integrator::symplectic), h_sym, int(1000 * period / h_sym));
  Real lo = e0, hi = e0;
  for (Real e : sym) { lo = std::min(lo, e); hi = std::max(hi, e); }
  MESSAGE("symplectic over 1000 periods: energy in [" << lo / e0 << ", " << hi / e0 << "] of the initial");
  CHECK(hi / e0 < 1.03);
  CHECK(lo / e0 > 0.97);
  CHECK(sym.back() / e0 == doctest::Approx(1).epsilon(0.03));

  // Backward Euler at h omega = 0.2 over 20 periods: strictly decreasing at every step.
  const Real h_imp = 0.02;
  const std::vector<Real> imp = energies(spring(Integrator::implicit), h_imp, int(20 * period / h_imp));
  bool monotone = imp.front() < e0;
  for (std::size_t k = 1; k < imp.size(); ++k) monotone = monotone && imp[k] < imp[k - 1];
  CHECK(monotone);
  // Amplification per step 1/sqrt(1 + (h omega)^2): energy factor (1 + 0.04)^-steps.
  CHECK(imp.back() / e0 == doctest::Approx(std::pow(1.04, -double(imp.size()))).epsilon(0.02));

  // Explicit Euler at a small step: energy factor (1 + (h omega)^2) per step, so it always grows.
  const Real h_eu = 1e-3;
  const std::vector<Real> eu = energies(spring(Integrator::euler), h_eu, int(20 * period / h_eu));
  MESSAGE("explicit Euler over 20 periods at h = 1 ms: energy x" << eu.back() / e0);
  CHECK(eu.back() / e0 == doctest::Approx(std::pow(1 + 1e-4, double(eu.size()))).epsilon(0.02));
  CHECK(eu.back() / e0 > 3);
}
