// The animated colliders' frames streamed during the run (sim/collider_track.h): a window of 4 frames a collider,
// holding at each frame what that frame's steps blend, read from the files as the run reaches them.
#include <doctest/doctest.h>

#include "tests/support/collision_scene.h"

using namespace clothsim;
using namespace clothsim::test;

TEST_CASE("a 12-frame collider sequence streams through a 4-frame window and is placed at each frame's position") {
  const auto dir = scratch_dir("collider_track");
  // A triangle 2 m from the cloth, rising 0.1 m per frame and shifted 1 m in x by the scene's transform.
  write_rising_triangle(dir, 12, 0.1, 2);
  write_text(dir / "s.xml", R"(<scene>
  <simulation timestep="0.005" fps="24" startFrame="1" endFrame="12"/>
  <static name="body" sequence="b.####.obj" translate="1 0 0"/>
  <cloth name="c" grid="3 3" size="0.1 0.1" translate="0 0.5 0"/>
</scene>)");
  const auto sc = load_collision_scene(dir / "s.xml");
  REQUIRE(sc.built.model.collision.colliders[0].frame_count == 12);
  int frames = 0;
  run_frames(sc, [&](int f, const Model&, const State&, const Workspace& ws) {
    const ColliderWindow& w = ws.collision.collider_frames[0];
    CHECK(w.x.size() == 4 * 3);  // 4 frames of 3 vertices, however long the sequence
    if (f == sc.built.options.start_frame) return;
    ++frames;
    CAPTURE(f);
    CHECK(w.count <= 4);
    // The last step ended on frame f: the body stands where frame f's file puts it, transformed.
    const Vec3 end = ws.collision.collider_x1[0];
    CHECK(end.x() == doctest::Approx(1).epsilon(1e-12));
    CHECK(end.y() == doctest::Approx(0.1 * (f - 1)).epsilon(1e-9));
    CHECK(end.z() == doctest::Approx(2).epsilon(1e-12));
  });
  CHECK(frames == 11);
}
