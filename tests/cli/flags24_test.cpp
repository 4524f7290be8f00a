// The 24-flag example: one OBJ, one stiffness map; stiffer flags (lighter grey) must stretch less.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "core/build_model.h"
#include "io/cloth_maps.h"
#include "io/obj_reader.h"
#include "io/scene_xml.h"
#include "tests/support/cli_harness.h"

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

TEST_CASE("24 flags in wind and gusts: they wave, and a stiffer flag stretches less than a softer one beside it") {
  const auto dir = scratch_dir("flags24");
  const CliResult r = run_cli("run " + scene_path + " --out " + dir.string() + " --quiet");
  REQUIRE_MESSAGE(r.exit_code == 0, r.output);
  const ObjFrame rest = parse_frame(read_text(dir / "flags.0001.obj"));
  REQUIRE(rest.v.size() == std::size_t(flags * per_flag));
  std::set<std::pair<int, int>> edges;
  for (const auto& t : rest.f)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));

  std::vector<Real> largest(flags, 0.0);
  // The free bottom corner of each flag (vertex k*35 + 34): its out-of-plane (z) position frame by frame.
  std::vector<std::vector<Real>> tip_z(flags);
  for (int frame = 2; frame <= 48; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "flags.%04d.obj", frame);
    const ObjFrame now = parse_frame(read_text(dir / name));
    REQUIRE(now.v.size() == rest.v.size());
    for (int k = 0; k < flags; ++k) tip_z[k].push_back(now.v[k * per_flag + per_flag - 1].z());
    for (const auto& [a, b] : edges) {
      const Real r0 = (rest.v[b] - rest.v[a]).norm();
      const Real strain = ((now.v[b] - now.v[a]).norm() - r0) / r0;
      largest[a / per_flag] = std::max(largest[a / per_flag], strain);
    }
  }
  // Each flag stretches more than the one below it in its column (six grey steps stiffer): the two hang 0.8 m
  // apart, well within one 4 m cell of the gust field, so they feel nearly the same wind. (Neighbours in a
  // row, one grey step apart, are a metre apart and only 4% different in stiffness at the stiff end.)
  for (int k = 0; k + 6 < flags; ++k) {
    INFO("flag " << k << ": " << largest[k] << ", flag " << k + 6 << ": " << largest[k + 6]);
    CHECK(largest[k + 6] < largest[k]);
  }
  // The flags wave: every free corner swings out of the flags' plane by centimetres and turns back and forth
  // (its frame-to-frame z motion changes direction several times), not one steady lean.
  for (int k = 0; k < flags; ++k) {
    const auto [lo, hi] = std::minmax_element(tip_z[k].begin(), tip_z[k].end());
    int turns = 0;
    for (std::size_t f = 2; f < tip_z[k].size(); ++f)
      turns += (tip_z[k][f] - tip_z[k][f - 1]) * (tip_z[k][f - 1] - tip_z[k][f - 2]) < 0;
    INFO("flag " << k << ": tip z range " << *hi - *lo << " m, " << turns << " turns");
    CHECK(*hi - *lo > 0.05);
    CHECK(turns >= 3);
  }
  // Ten times the stiffness: the softest flag stretches several times more than the stiffest.
  CHECK(largest[0] > 5 * largest[flags - 1]);
  CHECK(largest[flags - 1] > 0);
  // The colour texture passes through: the frames reference a material whose map_Kd finds stiffness.png.
  CHECK(read_text(dir / "flags.0001.obj").find("mtllib flags.mtl\n") != std::string::npos);
  CHECK(read_text(dir / "flags.mtl").find("map_Kd ") != std::string::npos);
}
