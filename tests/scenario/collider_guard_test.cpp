// The collider guard (systems/collision/collider_guard.h): after the strain limit's rounds that follow the
// collide stage, a cloth vertex found behind a collider surface within the reach is put back on it, and the
// inside/outside judgement at an edge or corner uses the feature's normal, not one face's.
#include <doctest/doctest.h>

#include "systems/collision/broad_phase.h"
#include "systems/collision/collider_guard.h"
#include "systems/collision/response.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;

namespace {

constexpr Real thickness = 0.003;

// A 4 cm sheet of 5 x 5 vertices lying at its thickness on a box whose top is y = 0, and a sharp square pyramid
// (apex at (0.3, 0, 0), base half-width 1 cm, height 10 cm) beside it, both static.
test::LoadedCollisionScene guard_scene() {
  const auto dir = test::scratch_dir("collider_guard");
  test::write_text(dir / "box.obj", test::box_obj(-0.1, 0.1, -0.1, 0, -0.1, 0.1));
  test::write_text(dir / "pyramid.obj", "v 0.3 0 0\nv 0.29 -0.1 -0.01\nv 0.31 -0.1 -0.01\nv 0.31 -0.1 0.01\n"
                                        "v 0.29 -0.1 0.01\nf 1 5 4\nf 1 4 3\nf 1 3 2\nf 1 2 5\nf 2 3 4\nf 2 4 5\n");
  test::write_text(dir / "scene.xml", R"(<scene>
  <simulation timestep="0.001" fps="100" startFrame="0" endFrame="1" integrator="implicit"/>
  <cloth name="sheet" grid="5 5" size="0.04 0.04" translate="0 0.003 0" maxStrain="0.1">
    <thickness value="0.003"/>
  </cloth>
  <static name="box" obj="box.obj"/>
  <static name="pyramid" obj="pyramid.obj"/>
</scene>)");
  return test::load_collision_scene(dir / "scene.xml");
}

}  // namespace

TEST_CASE("the collider guard puts a vertex found behind a surface onto it, and leaves the rest alone") {
  const auto sc = guard_scene();
  const Model& m = sc.built.model;
  Workspace ws = make_workspace(m, sc.built.options);
  State s = sc.built.state;
  build_broad_phase(m, s, s, ws.collision);
  // The collide stage left vertex 0 0.1 mm above the top, closer than the guard's margin (a pinch), so the way
  // back is no better: it goes onto the nearest surface.
  ws.collision.collided_x = s.x;
  ws.collision.collided_x[0].y() = 0.0001;
  s.x[0].y() = -0.002;   // 2 mm inside the box, within the 6 mm reach
  s.v[0] = Vec3(0.1, -0.5, 0);
  s.x[1].y() = -0.008;   // 8 mm inside: beyond the reach, left to the next collide stage
  s.x[2].y() = 0.0005;   // outside, closer than the thickness: the collide stage's business
  s.contact.assign(std::size_t(m.particle_count), ContactHold{});
  const State before = s;
  CHECK(guard_collider_surfaces(m, s, ws.collision, 1e-3) == 1);
  // On the top face plus a tenth of the thickness, straight up; the velocity into the box is gone, the rest kept.
  CHECK(s.x[0].x() == doctest::Approx(before.x[0].x()).epsilon(1e-12));
  CHECK(s.x[0].z() == doctest::Approx(before.x[0].z()).epsilon(1e-12));
  CHECK(s.x[0].y() == doctest::Approx(collider_guard_margin * thickness).epsilon(1e-12));
  CHECK(s.v[0].x() == doctest::Approx(0.1));
  CHECK(s.v[0].y() == doctest::Approx(0).scale(1));
  // Held on the top face from now on, the box's friction with the cloth's (neither set: the default).
  CHECK((s.contact[0].normal - Vec3(0, 1, 0)).norm() < 1e-12);
  CHECK(s.contact[0].velocity == Vec3::Zero());
  CHECK(s.contact[0].friction == doctest::Approx(collider_friction(m, 0, 0)));
  for (Index i = 1; i < m.particle_count; ++i) {
    CHECK(s.contact[i].normal == Vec3::Zero());
    CHECK(s.x[i] == before.x[i]);
    CHECK(s.v[i] == before.v[i]);
  }
}

TEST_CASE("the collider guard takes a vertex back the way it came, to where it is the margin outside") {
  const auto sc = guard_scene();
  const Model& m = sc.built.model;
  Workspace ws = make_workspace(m, sc.built.options);
  REQUIRE(ws.collision.collided_x.size() == std::size_t(m.particle_count));
  State s = sc.built.state;
  s.contact.assign(std::size_t(m.particle_count), ContactHold{});
  build_broad_phase(m, s, s, ws.collision);
  // The collide stage left vertex 0 3 mm above the box's top; the rounds then carried it 4 mm sideways and 5 mm
  // down, 2 mm into the box. Straight up would be 2.3 mm; back along its way, the margin (0.3 mm) above the top
  // is 46 % of the way.
  const Vec3 from = s.x[0];
  ws.collision.collided_x = s.x;
  s.x[0] = from + Vec3(0.004, -0.005, 0);
  CHECK(guard_collider_surfaces(m, s, ws.collision, 1e-3) == 1);
  const Real t = (collider_guard_margin * thickness + 0.002) / 0.005;
  CHECK(s.x[0].x() == doctest::Approx(from.x() + 0.004 * (1 - t)).epsilon(1e-6));
  CHECK(s.x[0].y() == doctest::Approx(collider_guard_margin * thickness).epsilon(1e-4));
  CHECK(s.x[0].z() == doctest::Approx(from.z()).epsilon(1e-12));
  CHECK((s.contact[0].normal - Vec3(0, 1, 0)).norm() < 1e-12);
}

TEST_CASE("inside or outside at a sharp corner: judged by the corner's normal, not by one face's plane") {
  const auto sc = guard_scene();
  const Model& m = sc.built.model;
  Workspace ws = make_workspace(m, sc.built.options);
  const CollisionScratch& s = ws.collision;
  const Vec3 apex(0.3, 0, 0);
  // 3 mm beside the apex, a little above it: outside the pyramid, yet behind the plane of the face on the far
  // side (its normal is nearly horizontal, pointing away). Its nearest point is the apex.
  const Vec3 beside = apex + Vec3(0.003, 0.001, 0);
  // 0.5 mm below the apex on the axis: inside.
  const Vec3 under = apex + Vec3(0, -0.0005, 0);
  int apex_triangles = 0, far_plane = 0;
  for (Index t = 0; t < Index(m.collision.mesh_tri_collider.size()); ++t) {
    const Index* v = &m.collision.mesh_tri_index[3 * t];
    const auto at_apex = [&](Index k) { return (s.collider_x1[v[k]] - apex).norm() < 1e-12; };
    if (!at_apex(0) && !at_apex(1) && !at_apex(2)) continue;
    ++apex_triangles;
    const Vec3 &a = s.collider_x1[v[0]], &b = s.collider_x1[v[1]], &c = s.collider_x1[v[2]];
    far_plane += (beside - a).dot((b - a).cross(c - a)) < 0;
    CHECK((closest_point_on_triangle(beside, a, b, c) - apex).norm() < 1e-12);
    CHECK_FALSE(behind_collider_triangle(m, s, t, beside, closest_point_and_weights(beside, a, b, c)));
    CHECK(behind_collider_triangle(m, s, t, under, closest_point_and_weights(under, a, b, c)));
  }
  CHECK(apex_triangles == 4);
  CHECK(far_plane >= 1);  // a face's own plane would have called the outside point inside
}
