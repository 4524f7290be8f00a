// The 24-flag example: one OBJ, one stiffness map; stiffer flags (lighter grey) must stretch less.
#include <doctest/doctest.h>

#include <cmath>
#include <set>
#include <sstream>

#include "cli_harness.h"
#include "core/build_model.h"
#include "io/cloth_maps.h"
#include "io/obj_reader.h"
#include "io/scene_xml.h"

using namespace clothsim;
using namespace clothsim::test;

namespace {

struct ObjFrame {
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;  // 0-based vertex indices
};

ObjFrame parse_frame(const std::string& text) {
  ObjFrame out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      Vec3 p;
      ls >> p[0] >> p[1] >> p[2];
      out.v.push_back(p);
    } else if (tag == "f") {
      std::array<int, 3> t{};
      for (int& c : t) {
        std::string corner;
        ls >> corner;
        c = std::stoi(corner.substr(0, corner.find('/'))) - 1;
      }
      out.f.push_back(t);
    }
  }
  return out;
}

constexpr int flags = 24, per_flag = 35;
const std::string scene_path = CLOTHSIM_SOURCE_DIR "/examples/flags24/flags24.xml";

}  // namespace

TEST_CASE("24 flags: flag k's springs take the stiffness of its grey block, rising with k") {
  const SceneDesc scene = io::read_scene(scene_path);
  REQUIRE(scene.cloths.size() == 1);
  MeshData mesh = io::read_obj(scene.cloths[0].obj);
  mesh.params = io::sample_cloth_maps(scene, scene.cloths[0], mesh);
  REQUIRE(mesh.vertex_count() == flags * per_flag);
  const BuiltScene built = build_model(scene, {mesh});
  CHECK(built.model.cloths[0].pieces == flags);
  CHECK(built.model.spring_kd.uniform());  // damping is one value: it stays a scalar
  const CliResult v = run_cli("validate " + scene_path);
  CHECK(v.exit_code == 0);
  CHECK(v.output.find("stiffness per element (mapped or scaled), damping one value, thickness one value") !=
        std::string::npos);
  // Every vertex of flag k lies inside its block of texels, so it reads grey round(255 k / 23) exactly.
  for (int k = 0; k < flags; ++k) {
    const Real expected = std::lerp(40.0, 400.0, std::round(255.0 * k / 23) / 255);
    for (int i = 0; i < per_flag; ++i) CHECK(mesh.params.stiffness[k * per_flag + i] == doctest::Approx(expected));
  }
}

TEST_CASE("24 flags: the largest strain over the run falls monotonically with the flag's grey") {
  const auto dir = scratch_dir("flags24");
  const CliResult r = run_cli("run " + scene_path + " --out " + dir.string() + " --quiet");
  REQUIRE_MESSAGE(r.exit_code == 0, r.output);
  const ObjFrame rest = parse_frame(read_text(dir / "flags.0001.obj"));
  REQUIRE(rest.v.size() == std::size_t(flags * per_flag));
  std::set<std::pair<int, int>> edges;
  for (const auto& t : rest.f)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));

  std::vector<Real> largest(flags, 0.0);
  for (int frame = 2; frame <= 48; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "flags.%04d.obj", frame);
    const ObjFrame now = parse_frame(read_text(dir / name));
    REQUIRE(now.v.size() == rest.v.size());
    for (const auto& [a, b] : edges) {
      const Real r0 = (rest.v[b] - rest.v[a]).norm();
      const Real strain = ((now.v[b] - now.v[a]).norm() - r0) / r0;
      largest[a / per_flag] = std::max(largest[a / per_flag], strain);
    }
  }
  for (int k = 0; k + 1 < flags; ++k) {
    INFO("flag " << k << ": " << largest[k] << ", flag " << k + 1 << ": " << largest[k + 1]);
    CHECK(largest[k + 1] < largest[k]);
  }
  // Ten times the stiffness: the softest flag stretches several times more than the stiffest.
  CHECK(largest[0] > 5 * largest[flags - 1]);
  CHECK(largest[flags - 1] > 0);
  // The colour texture passes through: the frames reference a material whose map_Kd finds stiffness.png.
  CHECK(read_text(dir / "flags.0001.obj").find("mtllib flags.mtl\n") != std::string::npos);
  CHECK(read_text(dir / "flags.mtl").find("map_Kd ") != std::string::npos);
}
