// External forces against closed forms: Provot's wind on a flat sheet, seeded random forces, transforms.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "core/transform.h"
#include "systems/forces.h"
#include "systems/random_force.h"
#include "systems/step.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;

TEST_CASE("wind on a flat sheet: a = k_w (n.(u - v)) n / density for every free particle") {
  SceneDesc s = test::grid_scene(6, 5, 1.0, Integrator::symplectic);
  s.simulation.gravity = Vec3::Zero();
  s.forces.wind_velocity = Vec3(3, 5, 0);  // normal component 5 m/s along +Y (the grid's normal)
  s.forces.wind_strength = 0.8;
  s.cloths[0].density = 0.2;
  BuiltScene b = test::build(s);
  b.state.v[7] = Vec3(0, 1, 0);  // a moving particle feels the relative speed (springs still at rest length)
  Workspace ws = make_workspace(b.model, b.options);
  eval_forces(b.model, b.state.x, b.state.v, 0, ws);
  for (Index i = 0; i < b.model.particle_count; ++i) {
    const Real un = i == 7 ? 4.0 : 5.0;
    CHECK(ws.f[i].x() == doctest::Approx(0).scale(1));
    CHECK(ws.f[i].y() == doctest::Approx(0.8 * un / 0.2).epsilon(1e-9));
  }
}

TEST_CASE("gravity, external acceleration and air damping add up, pinned particles get nothing") {
  // 5 x 5 grid pinned at its centre (12): the corner 0 shares no spring with the pin, and all its spring
  // neighbours move with it, so its springs add nothing and it sees only the accelerations.
  SceneDesc s = test::grid_scene(5, 5, 1.0, Integrator::symplectic);
  s.forces.external_acceleration = Vec3(1, 2, 3);
  s.forces.air_damping = 0.5;
  s.cloths[0].pins = {12};
  BuiltScene b = test::build(s);
  for (Index i = 0; i < b.model.particle_count; ++i)
    if (i != 12) b.state.v[i] = Vec3(2, 0, 0);  // uniform motion: the springs stay unstretched
  Workspace ws = make_workspace(b.model, b.options);
  eval_forces(b.model, b.state.x, b.state.v, 0, ws);
  CHECK(ws.f[12] == Vec3::Zero());
  const Vec3 a = ws.f[0];
  CHECK(a.x() == doctest::Approx(1 - 0.5 * 2).scale(1).epsilon(1e-12));  // external x minus air damping c v
  CHECK(a.y() == doctest::Approx(-9.81 + 2).epsilon(1e-12));
  CHECK(a.z() == doctest::Approx(3).epsilon(1e-12));
  // The pin's diagonal neighbour 6 moves across their shear spring, whose damping pulls it back: a fixture in
  // which the corner's springs were not idle would fail the checks above the same way.
  CHECK((ws.f[6] - a).norm() > 0.1);
}

TEST_CASE("random accelerations: reproducible from the seed, inside the allowed signs, uniform at the nodes") {
  RandomForceDesc r;
  r.amplitude = 2.0;
  r.seed = 42;
  r.allow = {true, true, false, true, true, false};  // x: both signs, y: positive only, z: negative only
  double sum[3] = {0, 0, 0};
  const int n = 20000;
  for (int p = 0; p < n; ++p) {
    // Lattice nodes (time 17 periods, space p cells along x): each value is one independent uniform draw.
    const Vec3 x(p * r.cell_size, 0, 0);
    const Vec3 a = random_acceleration(r, 17 * r.period, x);
    CHECK(a == random_acceleration(r, 17 * r.period, x));
    for (int axis = 0; axis < 3; ++axis) {
      CHECK(a[axis] >= (r.allow[2 * axis] ? -2.0 : 0.0));
      CHECK(a[axis] <= (r.allow[2 * axis + 1] ? 2.0 : 0.0));
      sum[axis] += a[axis];
    }
  }
  // Means of U(-2,2), U(0,2), U(-2,0) with a standard error of about 0.008 over 20000 draws.
  CHECK(sum[0] / n == doctest::Approx(0).scale(1).epsilon(0.05));
  CHECK(sum[1] / n == doctest::Approx(1).epsilon(0.05));
  CHECK(sum[2] / n == doctest::Approx(-1).epsilon(0.05));
  RandomForceDesc other = r;
  other.seed = 43;
  const Vec3 at(0.3, 0.1, -0.2);
  CHECK(random_acceleration(r, 0.7, at) != random_acceleration(other, 0.7, at));
  CHECK(random_acceleration(r, 0.7, at) != random_acceleration(r, 1.7, at));
}

TEST_CASE("random accelerations are gusts: neighbours and successive steps differ by the interpolation's bound") {
  RandomForceDesc r;
  r.amplitude = 3.0;  // range 6 m/s^2 per axis
  r.seed = 7;
  Real worst_space = 0, worst_time = 0;
  for (int p = 0; p < 2000; ++p) {
    const Vec3 x(0.37 * p, 0.011 * p, -0.023 * p);
    const Real t = 0.013 * p;
    const Vec3 a = random_acceleration(r, t, x);
    // Trilinear in space: |da| <= range |dx|_1 / cell; smoothstep in time: |da| <= 1.5 range dt / period.
    worst_space = std::max(worst_space, (random_acceleration(r, t, x + Vec3(0.01, 0.01, 0.01)) - a).cwiseAbs().maxCoeff());
    worst_time = std::max(worst_time, (random_acceleration(r, t + 1e-3, x) - a).cwiseAbs().maxCoeff());
  }
  CHECK(worst_space <= 6.0 * 0.03 / r.cell_size + 1e-12);
  CHECK(worst_time <= 1.5 * 6.0 * 1e-3 / r.period + 1e-12);
  CHECK(worst_space > 0.01);  // the field does vary
}

// Kinetic energy of a free 16 x 16 sheet (no gravity) after 1 s of random forces, symplectic Euler at step h.
static Real random_sheet_energy(Real h) {
  SceneDesc s = test::grid_scene(16, 16, 1.0, Integrator::symplectic, h);
  s.simulation.gravity = Vec3::Zero();
  s.forces.random.amplitude = 2.0;
  s.forces.random.seed = 3;
  s.cloths[0].stiffness = 20;  // well within the symplectic limit at 1 ms
  s.cloths[0].density = 1;
  BuiltScene b = test::build(s);
  const Model& m = b.model;
  State state = b.state, next = state;
  Workspace ws = make_workspace(m, b.options);
  for (int k = 0; k < int(std::lround(1.0 / h)); ++k) {
    step(m, b.options, state, next, ws, h);
    std::swap(state, next);
  }
  Real e = 0;
  for (Index i = 0; i < m.particle_count; ++i) e += 0.5 * state.v[i].squaredNorm() / m.particle_inv_mass[i];
  return e;
}

TEST_CASE("random forces do not depend on the time step: the energy after 1 s at 1 ms and 0.25 ms agrees") {
  // A fresh draw per step is a random walk (energy ~ h: 3.7x apart); the gust field is a fixed function of
  // position and time, so the two runs converge to the same motion.
  const Real coarse = random_sheet_energy(1e-3), fine = random_sheet_energy(2.5e-4);
  MESSAGE("kinetic energy after 1 s: " << coarse << " J at 1 ms, " << fine << " J at 0.25 ms");
  CHECK(coarse > 1e-3);
  CHECK(coarse / fine == doctest::Approx(1).epsilon(0.1));
}

TEST_CASE("transform: scale, then rotate about X, Y, Z (degrees), then translate") {
  TransformDesc t;
  t.rotate = Vec3(90, 0, 0);
  CHECK(apply_transform(t, Vec3(0, 0, 1)).isApprox(Vec3(0, -1, 0)));
  t.rotate = Vec3(90, 90, 0);  // X first: (0,0,1) -> (0,-1,0); Y leaves it
  CHECK(apply_transform(t, Vec3(0, 0, 1)).isApprox(Vec3(0, -1, 0)));
  t.rotate = Vec3(0, 90, 0);
  t.scale = Vec3(2, 2, 2);
  t.translate = Vec3(1, 2, 3);
  CHECK(apply_transform(t, Vec3(1, 0, 0)).isApprox(Vec3(1, 2, 1)));  // (2,0,0) about Y -> (0,0,-2), + t
}
