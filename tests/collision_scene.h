#pragma once
// Builds a scene written into a scratch folder the way `clothsim run` does (scene, cloth and collider meshes,
// Model, collision tables), for the collision tests.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_harness.h"
#include "core/build_collision.h"
#include "core/build_model.h"
#include "io/collider_reader.h"
#include "io/obj_reader.h"
#include "io/rest_shape.h"
#include "io/scene_xml.h"
#include "systems/step.h"

namespace clothsim::test {

struct LoadedCollisionScene {
  SceneDesc desc;
  BuiltScene built;
};

inline LoadedCollisionScene load_collision_scene(const std::filesystem::path& xml) {
  LoadedCollisionScene s;
  s.desc = io::read_scene(xml.string());
  std::vector<MeshData> meshes;
  for (const ClothDesc& c : s.desc.cloths) meshes.push_back(c.obj.empty() ? make_cloth_grid(c) : io::read_obj(c.obj));
  for (std::size_t c = 0; c < meshes.size(); ++c) meshes[c].rest_positions = io::read_rest_shape(s.desc, s.desc.cloths[c], meshes[c]);
  s.built = build_model(s.desc, meshes);
  build_collision(s.desc, io::read_colliders(s.desc), s.built.state.x, s.built.model);
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

// Runs every frame of a scene, calling check(frame, model, state, workspace) after each.
template <class Check>
void run_frames(LoadedCollisionScene& sc, Check&& check) {
  const Model& m = sc.built.model;
  State state = sc.built.state, scratch = state;
  Workspace ws = make_workspace(m);
  for (int f = m.start_frame; f <= m.end_frame; ++f) {
    if (f > m.start_frame) step_frame(m, state, scratch, ws);
    check(f, m, state, ws);
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
