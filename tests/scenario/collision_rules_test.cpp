// Rules of the collide stage that other stages and the input can break: collisions end the step (after the
// strain limit), cloth that starts inside a closed collider comes out, and an edge-edge contact's thickness does
// not depend on vertex numbering.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cstring>

#include "systems/collision/collide.h"
#include "systems/collision/collision_check.h"
#include "systems/collision/push_out.h"
#include "systems/step.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;
using clothsim::test::LoadedCollisionScene;
using clothsim::test::load_collision_scene;
using clothsim::test::run_frames;
using clothsim::test::scratch_dir;
using clothsim::test::write_text;

namespace {

// A closed unit cube centred at the origin, outward counter-clockwise faces.
const char* cube_obj = R"(v -0.5 -0.5 -0.5
v 0.5 -0.5 -0.5
v 0.5 0.5 -0.5
v -0.5 0.5 -0.5
v -0.5 -0.5 0.5
v 0.5 -0.5 0.5
v 0.5 0.5 0.5
v -0.5 0.5 0.5
f 1 4 3
f 1 3 2
f 5 6 7
f 5 7 8
f 1 5 8
f 1 8 4
f 2 3 7
f 2 7 6
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
)";

}  // namespace

TEST_CASE("collisions end the step: a strain-limited sheet pinned below a sphere's top never ends a step inside") {
  // A 9 x 9 sheet, 1 m wide, pinned along its x = +-0.5 edges at y = 0.2 over a sphere of radius 0.3: the path
  // over the sphere is 2.5% longer than the pins allow at maxStrain 0.01, so the limit and the contact disagree.
  // The limit before collisions (Bridson et al. 2002) leaves every step outside; after them it pulled the middle
  // back into the sphere.
  const auto dir = scratch_dir("rules_strain_order");
  std::string pins;
  for (int j = 0; j < 9; ++j) pins += std::to_string(9 * j) + " " + std::to_string(9 * j + 8) + " ";
  write_text(dir / "s.xml", R"(<scene>
  <simulation timestep="0.001" fps="100" startFrame="1" endFrame="31"/>
  <sphere name="ball" center="0 0 0" radius="0.3" friction="0.3"/>
  <cloth name="c" grid="9 9" size="1 1" translate="0 0.2 0" maxStrain="0.01">
    <density value="0.2"/><stiffness value="50"/><thickness value="0.005"/><pins vertices=")" + pins + R"("/>
  </cloth></scene>)");
  auto sc = load_collision_scene(dir / "s.xml");
  const Model& m = sc.built.model;
  REQUIRE(m.strain_limited);
  State s = sc.built.state, next = s;
  Workspace ws = make_workspace(m, sc.built.options);
  Real worst = 1;
  for (int k = 0; k < 300; ++k) {
    step(m, sc.built.options, s, next, ws, sc.built.options.dt);
    std::swap(s, next);
    if (k >= 5) worst = std::min(worst, min_collider_distance(m, s.x, ws.collision, 0));
  }
  CHECK(worst > 0.004);  // within the 5 mm thickness, never inside
  Real top = -1;
  for (const Vec3& p : s.x) top = std::max(top, p.y());
  CHECK(top > 0.3);  // the sheet does lie over the sphere's top
}

// A 10 x 10 sheet 3 cm under the top face of a closed unit cube, no gravity, for `frames` frames at 24 fps
// (the BVH: the cube's 1 m triangles would fill many of the hash's cloth-sized cells).
static LoadedCollisionScene cube_scene(int frames) {
  const auto dir = scratch_dir("rules_inside_cube");
  write_text(dir / "cube.obj", cube_obj);
  write_text(dir / "s.xml", R"(<scene>
  <simulation timestep="0.001" fps="24" startFrame="1" endFrame=")" + std::to_string(1 + frames) + R"(" gravity="0 0 0" broadPhase="bvh"/>
  <static name="cube" obj="cube.obj" friction="0.3"/>
  <cloth name="c" grid="10 10" size="0.5 0.5" translate="0 0.47 0">
    <density value="1"/><stiffness value="20"/><thickness value="0.005"/>
  </cloth></scene>)");
  return load_collision_scene(dir / "s.xml");
}

TEST_CASE("cloth that starts inside a closed collider is pushed out at the bounded speed: out in 0.07 s") {
  auto sc = cube_scene(6);
  const Model& m = sc.built.model;
  REQUIRE(m.collision.colliders[0].closed);
  Index at_start = -1, at_end = -1;
  Real lowest = 0;
  int frame_out = -1;
  run_frames(sc, [&](int f, const Model& model, const State& s, const Workspace& ws) {
    const Index inside = count_inside(model, s.x, ws.collision, 0);
    if (f == sc.built.options.start_frame) at_start = count_inside(model, s.x, ws.collision, 0);
    if (inside == 0 && frame_out < 0) frame_out = f;
    at_end = inside;
    lowest = 1;
    for (const Vec3& p : s.x) lowest = p.allFinite() ? std::min(lowest, p.y()) : -1;
  });
  CHECK(at_start == 100);
  CHECK(at_end == 0);
  CHECK(lowest > 0.5);  // above the top face, where the proximity pass keeps it
  // 3.5 cm (the depth and the thickness) at 0.5 m/s takes 0.07 s: out at frame 3 (1/24 s a frame), not sooner.
  CHECK(frame_out == 3);
}

TEST_CASE("the push-out gives the same bytes at 1 and 2 threads") {
  std::vector<Vec3> x[2];
  for (int t : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, t);
    auto sc = cube_scene(1);
    run_frames(sc, [&](int, const Model&, const State& s, const Workspace&) { x[t - 1] = s.x; });
  }
  REQUIRE(x[0].size() == x[1].size());
  CHECK(std::memcmp(x[0].data(), x[1].data(), x[0].size() * sizeof(Vec3)) == 0);
}

// Two cloths, one triangle each: an edge of cloth "thick" (1 cm) along x at y = 0 and an edge of cloth "thin"
// (2 mm) along z at y = 5 mm, crossing 5 mm apart at their midpoints; nothing else is within 1 cm. With the
// thicker side's thickness the edges touch, whichever cloth comes first.
static std::vector<std::array<Index, 3>> crossing_edges(bool thick_first) {
  const auto dir = scratch_dir("rules_edge_thickness");
  write_text(dir / "thick.obj", "v -1 0 0\nv 1 0 0\nv 0 -1 0\nf 1 3 2\n");
  write_text(dir / "thin.obj", "v 0 0.005 -1\nv 0 0.005 1\nv 0 1 0\nf 1 2 3\n");
  const std::string thick = R"(<cloth name="thick" obj="thick.obj"><thickness value="0.01"/></cloth>)";
  const std::string thin = R"(<cloth name="thin" obj="thin.obj"><thickness value="0.002"/></cloth>)";
  write_text(dir / "s.xml", "<scene>" + (thick_first ? thick + thin : thin + thick) + "</scene>");
  auto sc = load_collision_scene(dir / "s.xml");
  const Model& m = sc.built.model;
  Workspace ws = make_workspace(m, sc.built.options);
  const State& s = sc.built.state;
  build_broad_phase(m, s, s, ws.collision);
  return list_proximities(m, s, s, ws.collision, BroadMode::brute);
}

TEST_CASE("edge-edge contact thickness: renumbering the vertices does not change the contacts") {
  const auto a = crossing_edges(true), b = crossing_edges(false);
  // One edge-edge pair (kind 1), nothing else, in both orders.
  REQUIRE(a.size() == 1);
  REQUIRE(b.size() == 1);
  CHECK(a[0][0] == 1);
  CHECK(b[0][0] == 1);
}
