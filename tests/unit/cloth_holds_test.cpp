// The cloth-cloth holds of the strain limit after the collide stage (systems/collision/cloth_holds.h): which pairs
// are held, at what distance, and the projection's split against hand values.
#include <doctest/doctest.h>

#include <cmath>

#include "core/build_collision.h"
#include "core/build_model.h"
#include "systems/collision/cloth_holds.h"
#include "systems/collision/collide.h"
#include "systems/collision/collision_check.h"
#include "systems/strain_limit.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;

namespace {

// Triangle A in the plane y = 0, its centroid at the origin (corners 3 cm from it), and triangle B above it: its
// first vertex 2 mm over A's centroid, its other two 6 cm away and 2 cm up, so that B's only pair within the
// 3 mm thickness is that vertex over A. One self-colliding cloth of two pieces, no gravity.
BuiltScene stacked_triangles() {
  SceneDesc s = test::self_colliding_scene(0.003);
  s.cloths[0].max_strain = 0.1;
  MeshData mesh;
  const Real r = 0.03;
  for (int k = 0; k < 3; ++k) {
    const Real a = 2 * M_PI * k / 3;
    mesh.positions.push_back(Vec3(r * std::cos(a), 0, -r * std::sin(a)));
  }
  mesh.positions.push_back(Vec3(0, 0.002, 0));
  mesh.positions.push_back(Vec3(0.06, 0.022, 0.02));
  mesh.positions.push_back(Vec3(0.06, 0.022, -0.02));
  mesh.tri_index = {0, 1, 2, 3, 5, 4};
  BuiltScene b = build_model(s, std::vector<MeshData>{mesh});
  build_collision(s, {}, b.state.x, b.model);
  return b;
}

}  // namespace

TEST_CASE("cloth holds: the one pair within the thickness is held at the distance the collide stage left") {
  BuiltScene b = stacked_triangles();
  const Model& m = b.model;
  Workspace ws = make_workspace(m, b.options);
  State out = b.state;
  collide(m, b.state, out, ws, b.options.dt);
  // The collide stage eases the pair apart (0.1 of the overlap per step at most), so its distance is read back.
  const Real gap = out.x[3].y() - (out.x[0].y() + out.x[1].y() + out.x[2].y()) / 3;
  CHECK(gap > 0.002);
  CHECK(gap < 0.003);
  gather_cloth_holds(m, b.state, out, ws.collision);
  REQUIRE(ws.collision.cloth_holds.size() == 1);
  const Contact& k = ws.collision.cloth_holds[0];
  CHECK(k.kind == ContactKind::vertex_triangle);
  CHECK(k.a == 3);
  CHECK(k.b == 0);
  CHECK(k.n.y() == doctest::Approx(1).epsilon(1e-9));
  for (int j = 0; j < 3; ++j) CHECK(k.w[j] == doctest::Approx(1.0 / 3).epsilon(1e-6));
  CHECK(k.d == doctest::Approx(gap).epsilon(1e-9));

  SUBCASE("nothing to hold in two pieces that do not collide") {
    Model apart = m;
    apart.collision.cloth_contact = false;
    gather_cloth_holds(apart, b.state, out, ws.collision);
    CHECK(ws.collision.cloth_holds.empty());
  }
}

TEST_CASE("cloth holds: a vertex pushed through the triangle goes back to its distance, split by inverse mass") {
  BuiltScene b = stacked_triangles();
  const Model& m = b.model;
  Workspace ws = make_workspace(m, b.options);
  State out = b.state;
  gather_cloth_holds(m, b.state, out, ws.collision);
  REQUIRE(ws.collision.cloth_holds.size() == 1);
  Contact& k = ws.collision.cloth_holds[0];
  // Exact weights and distance, so that the hand values below are exact too.
  k.w[0] = k.w[1] = k.w[2] = 1.0 / 3;
  k.n = Vec3(0, 1, 0);
  k.d = 0.002;
  out.x[3].y() = -0.001;  // 1 mm under A: crossed
  const State before = out;
  const Real h = 0.01;
  CHECK(apply_cloth_holds(m, out, ws.collision, h) == 1);
  const Real iv = m.particle_inv_mass[3];
  Real weight = iv;
  for (int j = 0; j < 3; ++j) weight += m.particle_inv_mass[j] / 9;
  const Real lambda = 0.003 / weight;
  CHECK(out.x[3].y() == doctest::Approx(-0.001 + lambda * iv).epsilon(1e-12));
  for (int j = 0; j < 3; ++j) {
    CHECK(out.x[j].y() == doctest::Approx(-lambda * m.particle_inv_mass[j] / 3).epsilon(1e-12));
    CHECK(out.v[j].y() == doctest::Approx((out.x[j].y() - before.x[j].y()) / h).epsilon(1e-12));
  }
  const Real gap = out.x[3].y() - (out.x[0].y() + out.x[1].y() + out.x[2].y()) / 3;
  CHECK(gap == doctest::Approx(0.002).epsilon(1e-12));
  CHECK(count_intersecting_triangles(m, out.x) == 0);
  CHECK(count_intersecting_triangles(m, before.x) == 1);
  // A pair already as far apart as it was left does not move.
  CHECK(apply_cloth_holds(m, out, ws.collision, h) == 0);
  // The other vertices of B are untouched.
  CHECK(out.x[4] == before.x[4]);
  CHECK(out.x[5] == before.x[5]);
}

TEST_CASE("cloth holds inside the strain limit's sweeps: the limit and the hold both met where both can be") {
  // B's far vertices dragged 8 cm down: B's springs from vertex 3, 29 % long against a 10 % limit, pull it down
  // past A's plane unless the hold keeps it over A (which then moves down with it).
  BuiltScene b = stacked_triangles();
  const Model& m = b.model;
  Workspace ws = make_workspace(m, b.options);
  State start = b.state;
  start.contact.assign(std::size_t(m.particle_count), ContactHold{});  // no collider contact: the planes do nothing
  gather_cloth_holds(m, start, start, ws.collision);
  REQUIRE(ws.collision.cloth_holds.size() == 1);
  std::vector<Real> planes(std::size_t(m.particle_count), 0);
  for (bool hold : {false, true}) {
    CAPTURE(hold);
    State out = start;
    out.x[4] = Vec3(0.012, -0.08, 0.02);
    out.x[5] = Vec3(0.012, -0.08, -0.02);
    const auto held = [&](State& s, const MovedParticle& moved) { apply_cloth_holds(m, s, ws.collision, 0.01, moved); };
    if (hold) apply_strain_limit_on_contacts(m, out, 0.01, planes, held);
    else apply_strain_limit_on_contacts(m, out, 0.01, planes);
    CHECK(strain_limit_met(m, out.x));
    const Real gap = out.x[3].y() - (out.x[0].y() + out.x[1].y() + out.x[2].y()) / 3;
    if (hold) CHECK(gap >= 0.002 - 1e-9);
    else CHECK(gap < 0);
  }
}
