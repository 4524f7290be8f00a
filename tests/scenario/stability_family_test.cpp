// The damped stability estimate on a seeded family of small scenes: each runs at the advised step without
// diverging, and at twice its estimated limit diverges where the estimate is an exact mode (docs/stability.md).
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>

#include "io/scene_family.h"
#include "systems/auto_step.h"
#include "systems/spring_jacobian.h"
#include "systems/stability.h"
#include "tests/support/collision_scene.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;
using namespace clothsim::test;

namespace {

constexpr int family_size = 24;
constexpr int stable_steps_run = 400;    // at least 60 periods of the stiffest mode at the advised step
constexpr int unstable_steps_run = 2000; // the slowest growth in the family (explicit Euler, light damping)

BuiltScene load_family(int seed) {
  BuiltScene b = load_scene_text("family_" + std::to_string(seed), io::family_scene(seed).xml).built;
  io::perturb_start(b.model, b.state, 1e-4);
  return b;
}

// The two-particle spring, its free end moved by 1e-4 m.
bool diverges(const BuiltScene& b, Real h, int steps) {
  State s = b.state;
  io::perturb_start(b.model, s, 1e-4);
  return run_diverges(b.model, b.options, s, h, steps);
}

// Exact explicit-Euler limit of the scene linearised at x: the step map is I + h S with S = [[0, I], [-M^-1 K,
// -M^-1 C]], so each eigenvalue lambda of S needs |1 + h lambda| <= 1, h <= -2 Re(lambda) / |lambda|^2. Neutral
// modes (lambda = 0: rigid motion, sideways motion of a straight spring) are left out.
Real dense_euler_limit(const Model& m, const std::vector<Vec3>& x) {
  std::vector<Index> slot(m.particle_count, -1);
  Index free = 0;
  for (Index i = 0; i < m.particle_count; ++i)
    if (m.particle_inv_mass[i] > 0) slot[i] = free++;
  const Index n = 3 * free;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n), C = K, S = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (Index s = 0; s < m.spring_count; ++s) {
    const Index a = m.spring_a[s], b = m.spring_b[s];
    const SpringJacobian j = spring_jacobian(x[a], x[b], m.spring_rest[s], m.spring_ke[s], m.spring_kd[s]);
    for (auto [D, block] : {std::pair{&K, Mat3(j.dfdx)}, std::pair{&C, Mat3(j.dfdv)}}) {
      if (slot[a] >= 0) D->block<3, 3>(3 * slot[a], 3 * slot[a]) += block;
      if (slot[b] >= 0) D->block<3, 3>(3 * slot[b], 3 * slot[b]) += block;
      if (slot[a] >= 0 && slot[b] >= 0) {
        D->block<3, 3>(3 * slot[a], 3 * slot[b]) -= block;
        D->block<3, 3>(3 * slot[b], 3 * slot[a]) -= block;
      }
    }
  }
  S.topRightCorner(n, n).setIdentity();
  for (Index i = 0; i < m.particle_count; ++i)
    if (slot[i] >= 0)
      for (Index r = 3 * slot[i]; r < 3 * slot[i] + 3; ++r) {
        S.row(n + r).head(n) = -m.particle_inv_mass[i] * K.row(r);
        S.row(n + r).tail(n) = -m.particle_inv_mass[i] * C.row(r);
        S(n + r, n + r) -= m.air_damping;
      }
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(S, false).eigenvalues();
  const Real scale = lambda.cwiseAbs().maxCoeff();
  Real limit = INFINITY;
  for (const std::complex<Real>& l : lambda)
    if (std::abs(l) > 1e-6 * scale) limit = std::min(limit, -2 * l.real() / std::norm(l));
  return limit;
}

}  // namespace

TEST_CASE("explicit Euler's floor (kd/ke)_min + c / w_max^2 holds where the probes do not: family scene 6") {
  // Bend springs at 0.1 ke with the same kd: kd/ke differs between springs, and no probe is an exact mode. At
  // rest (unperturbed) every spring is straight at its rest length, so K = sum ke n n^T, as the estimate takes it.
  const BuiltScene b = load_scene_text("family_floor", io::family_scene(6).xml).built;
  const DampedModes d = estimate_modes(b.model, b.state.x);
  const Real probes = std::min(mode_step_limit(Integrator::euler, d.omega_max, d.gamma_of_stiff),
                               mode_step_limit(Integrator::euler, d.omega_of_damped, d.gamma_max));
  const Real exact = dense_euler_limit(b.model, b.state.x);
  const Real floor = stable_steps(d).euler;
  MESSAGE("explicit Euler limit: probes " << probes << " s, exact " << exact << " s, floor " << floor << " s");
  CHECK(floor == doctest::Approx(0.0918126 / 3434.82).epsilon(1e-5));  // its kd / ke, no air damping
  CHECK(floor <= exact);           // 2.673e-5 s against 2.778e-5 s: 4% below
  CHECK(exact < 1.05 * floor);
  CHECK(probes > 1.15 * exact);    // 3.299e-5 s: 19% above, which auto's stepSafety 0.7 had to absorb
}

TEST_CASE("damped oscillator limits: closed forms at their edges, RK4's undamped 2 sqrt(2)/omega") {
  // Symplectic Euler on u'' = -w^2 u - g u': trace 2 - h^2 w^2 - h g, determinant 1 - h g (Jury): h^2 w^2 + 2 h g < 4.
  const Real w = 100, g = 30;
  const Real h = mode_step_limit(Integrator::symplectic, w, g);
  CHECK(h * h * w * w + 2 * h * g == doctest::Approx(4).epsilon(1e-12));
  CHECK(mode_step_limit(Integrator::symplectic, 0, g) == doctest::Approx(2 / g));  // h lambda < 2, damping alone
  CHECK(mode_step_limit(Integrator::symplectic, w, 0) == doctest::Approx(2 / w));
  CHECK(mode_step_limit(Integrator::rk4, w, 0) == doctest::Approx(2 * std::sqrt(2.0) / w).epsilon(1e-9));
  CHECK(mode_step_limit(Integrator::rk4, 0, g) * g == doctest::Approx(2.785293563).epsilon(1e-6));  // real axis
  CHECK(mode_step_limit(Integrator::euler, w, g) == doctest::Approx(g / (w * w)));  // |1 + h lambda|^2 = 1 - hg + h^2 w^2
  CHECK(mode_step_limit(Integrator::euler, w, 0) == 0);
  CHECK(mode_step_limit(Integrator::euler, 0, g) == doctest::Approx(2 / g));
  // Spring damping lowers the symplectic limit below the undamped 2/w.
  CHECK(h < 2 / w);
}

TEST_CASE("the damped limit is sharp on the two-particle spring: stable at 0.97x, diverging at 1.03x") {
  // One free 0.01 kg mass on k = 400 N/m, kd = 1 N s/m: w = 200 rad/s, g = 100 1/s (the damping dominates).
  for (Integrator integ : {Integrator::symplectic, Integrator::rk4, Integrator::euler}) {
    const BuiltScene s = two_particle_spring(400, 1, 0.01, 1, 0.01, integ);
    const StableSteps l = stable_steps(estimate_modes(s.model, s.state.x));
    CHECK(l.omega_max == doctest::Approx(200));
    CHECK(l.gamma_max == doctest::Approx(100));
    const Real limit = stable_step_limit(l, integ);
    CHECK(!diverges(s, 0.97 * limit, 3000));
    CHECK(diverges(s, 1.03 * limit, 3000));
  }
}

TEST_CASE("the seeded family runs at the advised step and diverges at twice the limit where the mode is exact") {
  int proportional = 0, with_damping = 0;
  for (int seed = 0; seed < family_size; ++seed) {
    const BuiltScene b = load_family(seed);
    const StableSteps l = stable_steps(estimate_modes(b.model, b.state.x));
    const Real limit = stable_step_limit(l, b.options.integrator);
    const Real advised = auto_step_target(b.options, l);
    CAPTURE(seed);
    CAPTURE(limit);
    REQUIRE(limit > 0);
    CHECK(!run_diverges(b.model, b.options, b.state, advised, stable_steps_run));
    // Theory: the stiffest mode's amplitude grows by rho a step at 2x; the perturbation (1e-4 m) carries the
    // energy past the run guard's bound within the run when rho^steps > 1e6.
    const DampedModes d = estimate_modes(b.model, b.state.x);
    const Real rho = mode_amplification(b.options.integrator, d.omega_max, d.gamma_of_stiff, 2 * limit);
    if (io::family_scene(seed).proportional && unstable_steps_run * std::log(rho) > std::log(1e6)) {
      ++proportional;
      CHECK(run_diverges(b.model, b.options, b.state, 2 * limit, unstable_steps_run));
    }
    if (l.gamma_max > 0) ++with_damping;
  }
  // The draw covers both kinds of scene (hand count of the seeds).
  CHECK(proportional >= 8);
  CHECK(with_damping >= 16);
}
