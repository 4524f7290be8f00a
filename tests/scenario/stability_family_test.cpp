// The damped stability estimate on a seeded family of small scenes: each runs at the advised step without
// diverging, and at twice its estimated limit diverges where the estimate is an exact mode (docs/stability.md).
#include <doctest/doctest.h>

#include <cmath>

#include "io/scene_family.h"
#include "systems/auto_step.h"
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
  const auto dir = scratch_dir("family_" + std::to_string(seed));
  write_text(dir / "scene.xml", io::family_scene(seed).xml);
  BuiltScene b = load_collision_scene(dir / "scene.xml").built;
  io::perturb_start(b.model, b.state, 1e-4);
  return b;
}

// The two-particle spring, its free end moved by 1e-4 m.
bool diverges(const BuiltScene& b, Real h, int steps) {
  State s = b.state;
  io::perturb_start(b.model, s, 1e-4);
  return run_diverges(b.model, b.options, s, h, steps);
}

}  // namespace

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
