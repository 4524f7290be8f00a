// External forces against closed forms: Provot's wind on a flat sheet, seeded random forces, transforms.
#include <doctest/doctest.h>

#include <cmath>

#include "core/transform.h"
#include "scene_fixtures.h"
#include "systems/forces.h"
#include "systems/random_force.h"

using namespace clothsim;

TEST_CASE("wind on a flat sheet: a = k_w (n.(u - v)) n / density for every free particle") {
  SceneDesc s = test::grid_scene(6, 5, 1.0, Integrator::symplectic);
  s.simulation.gravity = Vec3::Zero();
  s.forces.wind_velocity = Vec3(3, 5, 0);  // normal component 5 m/s along +Y (the grid's normal)
  s.forces.wind_strength = 0.8;
  s.cloths[0].density = 0.2;
  BuiltScene b = test::build(s);
  b.state.v[7] = Vec3(0, 1, 0);  // a moving particle feels the relative speed (springs still at rest length)
  Workspace ws = make_workspace(b.model);
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
  Workspace ws = make_workspace(b.model);
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

TEST_CASE("random accelerations: reproducible from the seed, inside the allowed signs, uniform") {
  RandomForceDesc r;
  r.amplitude = 2.0;
  r.seed = 42;
  r.allow = {true, true, false, true, true, false};  // x: both signs, y: positive only, z: negative only
  double sum[3] = {0, 0, 0};
  const int n = 20000;
  for (int p = 0; p < n; ++p)
    for (int axis = 0; axis < 3; ++axis) {
      const Real a = random_acceleration(r, 17, p, axis);
      CHECK(a == random_acceleration(r, 17, p, axis));
      CHECK(a >= (r.allow[2 * axis] ? -2.0 : 0.0));
      CHECK(a <= (r.allow[2 * axis + 1] ? 2.0 : 0.0));
      sum[axis] += a;
    }
  // Means of U(-2,2), U(0,2), U(-2,0) with a standard error of about 0.008 over 20000 draws.
  CHECK(sum[0] / n == doctest::Approx(0).scale(1).epsilon(0.05));
  CHECK(sum[1] / n == doctest::Approx(1).epsilon(0.05));
  CHECK(sum[2] / n == doctest::Approx(-1).epsilon(0.05));
  RandomForceDesc other = r;
  other.seed = 43;
  CHECK(random_acceleration(r, 17, 5, 0) != random_acceleration(other, 17, 5, 0));
  CHECK(random_acceleration(r, 17, 5, 0) != random_acceleration(r, 18, 5, 0));
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
