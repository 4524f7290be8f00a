// Integrators against closed forms: free fall (with the known first-order offsets of the Euler methods), the
// damped and undamped two-particle spring, and the measured convergence order of each method.
#include <doctest/doctest.h>

#include <cmath>

#include "systems/step.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;

namespace {

Vec3 centre_of_mass(const Model& m, const State& s) {
  Vec3 sum = Vec3::Zero();
  Real mass = 0;
  for (Index i = 0; i < m.particle_count; ++i) {
    sum += s.x[i] / m.particle_inv_mass[i];
    mass += 1 / m.particle_inv_mass[i];
  }
  return sum / mass;
}

// Free fall of an unpinned 8x8 sheet for n steps of h from rest at y0 with initial velocity v0.
Vec3 free_fall(Integrator integrator, Real h, int n, const Vec3& v0, Vec3& com0) {
  SceneDesc scene = test::grid_scene(8, 8, 1.0, integrator, h);
  scene.cloths[0].stiffness = 20;  // well inside every method's stability limit at h = 1e-3
  BuiltScene b = test::build(scene);
  for (Vec3& v : b.state.v) v = v0;
  com0 = centre_of_mass(b.model, b.state);
  Workspace ws = make_workspace(b.model, b.options);
  State scratch = b.state;
  for (int k = 0; k < n; ++k) {
    step(b.model, b.options, b.state, scratch, ws, h);
    std::swap(b.state, scratch);
  }
  return centre_of_mass(b.model, b.state);
}

// Position of the free particle of test::two_particle_spring at time t (closed form, underdamped).
Real spring_closed_form(Real k, Real kd, Real m, Real rest, Real stretch, Real t) {
  const Real w0 = std::sqrt(k / m), zeta = kd / (2 * std::sqrt(k * m));
  const Real wd = w0 * std::sqrt(1 - zeta * zeta);
  return rest + stretch * std::exp(-zeta * w0 * t) * (std::cos(wd * t) + zeta * w0 / wd * std::sin(wd * t));
}

Real spring_error(Integrator integrator, Real kd, Real h, Real t_end) {
  const Real k = 100, m = 1, rest = 1, stretch = 0.1;
  BuiltScene b = test::two_particle_spring(k, kd, m, rest, stretch, integrator);
  Workspace ws = make_workspace(b.model, b.options);
  State scratch = b.state;
  const int n = int(std::lround(t_end / h));
  for (int s = 0; s < n; ++s) {
    step(b.model, b.options, b.state, scratch, ws, h);
    std::swap(b.state, scratch);
  }
  return std::abs(b.state.x[1].x() - spring_closed_form(k, kd, m, rest, stretch, n * h));
}

Real measured_order(Integrator integrator, Real kd, Real h, Real t_end) {
  return std::log2(spring_error(integrator, kd, h, t_end) / spring_error(integrator, kd, h / 2, t_end));
}

}  // namespace

TEST_CASE("free fall: RK4 is exact, the Euler methods carry their known first-order offsets") {
  const Real h = 1e-3, g = -9.81;
  const int n = 500;
  const Real t = n * h;
  const Vec3 v0(0.3, 1.5, -0.2);
  for (Integrator integrator : {Integrator::rk4, Integrator::euler, Integrator::symplectic}) {
    Vec3 com0;
    const Vec3 com = free_fall(integrator, h, n, v0, com0);
    Vec3 expected = com0 + v0 * t + Vec3(0, 0.5 * g * t * t, 0);
    if (integrator == Integrator::euler) expected.y() -= 0.5 * g * t * h;
    if (integrator == Integrator::symplectic) expected.y() += 0.5 * g * t * h;
    CAPTURE(int(integrator));
    CHECK((com - expected).norm() <= 1e-9 * expected.norm());
    // The offset itself is large enough to be told apart from exactness: 0.5 g t h = 2.45e-3 m here.
    if (integrator != Integrator::rk4) CHECK(std::abs(com.y() - (com0.y() + v0.y() * t + 0.5 * g * t * t)) > 2e-3);
  }
}

TEST_CASE("two-particle spring follows the closed-form oscillator") {
  // omega = 10 rad/s, 1.6 periods. Errors at these steps are small against the 0.1 m amplitude.
  CHECK(spring_error(Integrator::rk4, 0.0, 1e-3, 1.0) < 1e-9);
  CHECK(spring_error(Integrator::rk4, 2.0, 1e-3, 1.0) < 1e-9);
  CHECK(spring_error(Integrator::symplectic, 0.0, 1e-4, 1.0) < 1e-3);
  CHECK(spring_error(Integrator::symplectic, 2.0, 1e-4, 1.0) < 1e-3);
  CHECK(spring_error(Integrator::euler, 2.0, 1e-5, 1.0) < 1e-3);
}

TEST_CASE("measured convergence orders: Euler methods 1, RK4 4") {
  for (Real kd : {0.0, 2.0}) {
    CAPTURE(kd);
    CHECK(measured_order(Integrator::euler, kd, 1e-4, 1.0) == doctest::Approx(1.0).epsilon(0.1));
    CHECK(measured_order(Integrator::symplectic, kd, 1e-3, 1.0) == doctest::Approx(1.0).epsilon(0.1));
    CHECK(measured_order(Integrator::rk4, kd, 1e-2, 1.0) == doctest::Approx(4.0).epsilon(0.05));
  }
}

TEST_CASE("steps per frame divide a frame evenly, with a tolerance for 1/(fps*dt) close to an integer") {
  SimulationDesc sim;
  sim.fps = 24;
  sim.timestep = 1.0 / 240;
  CHECK(steps_per_frame(sim) == 10);
  sim.timestep = 0.001;
  CHECK(steps_per_frame(sim) == 42);  // 41.67 -> 42 steps of 1/1008 s
  sim.timestep = 1.0;
  CHECK(steps_per_frame(sim) == 1);
}
