#pragma once
// Builds a scene written into a scratch folder the way `clothsim run` does (scene, cloth and collider meshes,
// Model, collision tables), for the collision tests.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <type_traits>

#include "sim/load_scene.h"
#include "sim/simulation.h"
#include "tests/support/cli_harness.h"

namespace clothsim::test {

using LoadedCollisionScene = sim::LoadedScene;

// The scene as `clothsim run` loads it (sim/load_scene.h): meshes, maps, rest shapes, colliders, auto step.
inline sim::LoadedScene load_collision_scene(const std::filesystem::path& xml) { return sim::load_scene(xml.string()); }

// The scene text `xml` written as scene.xml in a fresh scratch folder `name`, loaded as above.
inline sim::LoadedScene load_scene_text(const std::string& name, const std::string& xml) {
  const auto dir = scratch_dir(name);
  write_text(dir / "scene.xml", xml);
  return load_collision_scene(dir / "scene.xml");
}

// A scene of one self-colliding mesh cloth (`<generated>`: the test supplies the mesh) of the given thickness,
// without gravity, 1 ms steps.
inline SceneDesc self_colliding_scene(Real thickness) {
  SceneDesc s;
  s.path = "<test>";
  s.simulation.timestep = 1e-3;
  s.simulation.fps = 1000;
  s.simulation.gravity = Vec3::Zero();
  ClothDesc c;
  c.name = "panels";
  c.obj = "<generated>";
  c.self_collision = true;
  c.thickness = thickness;
  s.cloths.push_back(c);
  return s;
}

// The shared data folder beside the checkout (../shared/data), or beside the folder holding it (a worktree under
// wt/); CLOTHSIM_SHARED_DATA overrides. Empty when absent: the tests that use it then skip.
inline std::filesystem::path shared_data() {
  if (const char* env = std::getenv("CLOTHSIM_SHARED_DATA")) return env;
  const std::filesystem::path root = CLOTHSIM_SOURCE_DIR;
  for (const auto& up : {root.parent_path(), root.parent_path().parent_path()})
    if (std::filesystem::is_directory(up / "shared" / "data")) return up / "shared" / "data";
  return {};
}

// The Kick animation of the shared data (colliders/animated/cipc_kick), or empty when the data is absent: the
// tests that use it then skip.
inline std::filesystem::path kick_sequence() {
  const std::filesystem::path data = shared_data();
  if (data.empty() || !std::filesystem::is_directory(data / "colliders" / "animated" / "cipc_kick")) return {};
  return data / "colliders" / "animated" / "cipc_kick";
}

// The Kick drop of docs/performance.md, frames first..last: the 24 x 24 sheet (0.9 m, 6 mm thick, density 0.3,
// stiffness 150, bend 0.1, damping 0.02, friction 0.5, air damping 0.2) at rest, centred at `at`, over the body
// (friction 0.5), 0.4 ms steps at 25 fps, collisionIterations 2; `cloth_extra` adds attributes to <cloth>.
inline std::string kick_scene(const std::filesystem::path& sequence, int first, int last, const Vec3& at,
                              const std::string& cloth_extra = "") {
  char head[512];
  std::snprintf(head, sizeof head, R"(<scene>
  <simulation timestep="0.0004" fps="25" startFrame="%d" endFrame="%d" collisionIterations="2"/>
  <forces><airDamping value="0.2"/></forces>
)", first, last);
  char cloth[512];
  std::snprintf(cloth, sizeof cloth, R"(  <cloth name="sheet" grid="24 24" size="0.9 0.9" translate="%.17g %.17g %.17g" friction="0.5" %s>
    <density value="0.3"/><stiffness value="150" bend="0.1"/><damping value="0.02"/><thickness value="0.006"/>
  </cloth></scene>)", at.x(), at.y(), at.z(), cloth_extra.c_str());
  return std::string(head) + R"(  <static name="body" sequence=")" + (sequence / "shell#.obj.gz").string() +
         R"(" friction="0.5"/>
)" + cloth;
}

// An axis-aligned box [x0, x1] x [y0, y1] x [z0, z1] as an OBJ with outward triangles.
inline std::string box_obj(Real x0, Real x1, Real y0, Real y1, Real z0, Real z1) {
  std::string text;
  char line[96];
  for (Real x : {x0, x1})
    for (Real y : {y0, y1})
      for (Real z : {z0, z1}) {
        std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", x, y, z);
        text += line;
      }
  // corner index x*4 + y*2 + z, 1-based below
  const int f[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                        {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  for (const auto& t : f) text += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
                                  std::to_string(t[2] + 1) + "\n";
  return text;
}

// Runs every frame of a scene through the run's frame loop (sim::Simulation), calling
// check(frame, model, state, workspace) after each, or check(frame, model, state, workspace, report) for the
// frame's figures (contacts, zones, steps). A diverged frame fails the test.
template <class Check>
void run_frames(const sim::LoadedScene& sc, Check&& check) {
  sim::Simulation simulation(sc);
  while (simulation.next_frame() <= simulation.options().end_frame) {
    const sim::FrameReport r = simulation.advance_frame();
    INFO(r.divergence);
    REQUIRE_FALSE(r.diverged);
    if constexpr (std::is_invocable_v<Check, int, const Model&, const State&, const Workspace&, const sim::FrameReport&>)
      check(r.frame, simulation.model(), simulation.state(), simulation.workspace(), r);
    else
      check(r.frame, simulation.model(), simulation.state(), simulation.workspace());
  }
}

// An animated collider sequence b.0001.obj .. b.NNNN.obj in dir: one triangle (0, y, z), (1, y, z), (0, y, z + 1)
// at y = rise x (frame - 1).
inline void write_rising_triangle(const std::filesystem::path& dir, int frames, Real rise, Real z) {
  for (int f = 1; f <= frames; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "b.%04d.obj", f);
    const std::string y = std::to_string(rise * (f - 1)), zs = std::to_string(z), z1 = std::to_string(z + 1);
    write_text(dir / name, "v 0 " + y + " " + zs + "\nv 1 " + y + " " + zs + "\nv 0 " + y + " " + z1 + "\nf 1 3 2\n");
  }
}

// A UV sphere (closed, outward counter-clockwise normals) as OBJ text, centred at c.
inline std::string sphere_obj(const Vec3& c, Real r, int rings = 12, int segments = 24) {
  std::string s;
  auto vtx = [&](const Vec3& p) {
    s += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  };
  vtx(c + Vec3(0, r, 0));
  for (int i = 1; i < rings; ++i) {
    const Real th = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      const Real ph = 2 * M_PI * j / segments;
      vtx(c + r * Vec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)));
    }
  }
  vtx(c - Vec3(0, r, 0));
  auto ring = [&](int i, int j) { return 2 + (i - 1) * segments + (j % segments); };  // 1-based OBJ index
  const int bottom = 2 + (rings - 1) * segments;
  for (int j = 0; j < segments; ++j) {
    s += "f 1 " + std::to_string(ring(1, j + 1)) + " " + std::to_string(ring(1, j)) + "\n";
    for (int i = 1; i < rings - 1; ++i) {
      s += "f " + std::to_string(ring(i, j)) + " " + std::to_string(ring(i, j + 1)) + " " +
           std::to_string(ring(i + 1, j + 1)) + "\n";
      s += "f " + std::to_string(ring(i, j)) + " " + std::to_string(ring(i + 1, j + 1)) + " " +
           std::to_string(ring(i + 1, j)) + "\n";
    }
    s += "f " + std::to_string(bottom) + " " + std::to_string(ring(rings - 1, j)) + " " +
         std::to_string(ring(rings - 1, j + 1)) + "\n";
  }
  return s;
}

}  // namespace clothsim::test
