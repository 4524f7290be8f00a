// Collider input: sequences, frame names, and the exit code 2 errors that name the file.
#include <doctest/doctest.h>
#include <zlib.h>

#include <fstream>

#include "core/build_collision.h"
#include "io/collider_reader.h"
#include "io/scene_xml.h"
#include "systems/collision/collide.h"
#include "tests/support/cli_harness.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;
using namespace clothsim::test;

TEST_CASE("sequence frame names: the run of '#' is the zero-padded frame number") {
  CHECK(io::sequence_frame_path("dir/body.####.obj", 7) == "dir/body.0007.obj");
  CHECK(io::sequence_frame_path("b#.obj", 12) == "b12.obj");
  CHECK(io::sequence_frame_path("a#b/x.##.obj", 3) == "a#b/x.03.obj");
}

namespace {
const char* tri_obj = "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 3 2\n";
const char* quad_obj = "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 1 0 1\nf 1 3 2\nf 2 3 4\n";
std::string scene_with(const std::string& collider) {
  return "<scene>\n<simulation fps=\"24\" startFrame=\"1\" endFrame=\"3\"/>\n" + collider +
         "\n<cloth name=\"c\" grid=\"3 3\" translate=\"0 0.5 0\" saveDir=\"out\"/>\n</scene>\n";
}
}  // namespace

namespace {
// text gzip-compressed into path (zlib, as gzip(1) would).
void write_gzip(const std::filesystem::path& path, const std::string& text) {
  gzFile out = gzopen(path.string().c_str(), "wb");
  REQUIRE(out != nullptr);
  REQUIRE(gzwrite(out, text.data(), unsigned(text.size())) == int(text.size()));
  REQUIRE(gzclose(out) == Z_OK);
}
}  // namespace

TEST_CASE("an unpadded, gzip-compressed sequence (shell#.obj.gz) reads the same frames as plain OBJs") {
  // Frames 9..11 cross a digit boundary: shell9, shell10, shell11 (no padding), each moved up by its number.
  const auto dir = scratch_dir("collider_gzip");
  for (int f = 9; f <= 11; ++f) {
    const std::string obj = "v 0 " + std::to_string(f) + " 0\nv 1 " + std::to_string(f) + " 0\nv 0 " +
                            std::to_string(f) + " 1\nf 1 3 2\n";
    write_gzip(dir / ("shell" + std::to_string(f) + ".obj.gz"), obj);
    write_text(dir / ("plain" + std::to_string(f) + ".obj"), obj);
  }
  auto scene = [&](const std::string& pattern) {
    write_text(dir / "s.xml", "<scene>\n<simulation fps=\"24\" startFrame=\"9\" endFrame=\"11\"/>\n"
                              "<static name=\"body\" sequence=\"" + pattern + "\"/>\n<cloth name=\"c\" grid=\"3 3\"/>\n</scene>\n");
    return io::read_scene((dir / "s.xml").string());
  };
  const SceneDesc gz = scene("shell#.obj.gz"), plain = scene("plain#.obj");
  const auto meshes = io::read_colliders(gz);
  REQUIRE(meshes[0].mesh);
  CHECK(meshes[0].first_frame == 9);
  CHECK(meshes[0].frame_count == 3);
  CHECK(meshes[0].mesh->positions == io::read_collider_frame(plain, 0, 9).positions);
  for (int f = 9; f <= 11; ++f) {
    const MeshData a = io::read_collider_frame(gz, 0, f), b = io::read_collider_frame(plain, 0, f);
    CHECK(a.positions == b.positions);
    CHECK(a.tri_index == b.tri_index);
    CHECK(a.positions[0].y() == f);
  }
}

TEST_CASE("a corrupt gzip frame stops the run with exit code 2 naming that file") {
  const auto dir = scratch_dir("collider_bad_gzip");
  write_gzip(dir / "full.gz", std::string(quad_obj) + std::string(4000, '#') + "\n");
  std::ifstream in(dir / "full.gz", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* name : {"b1.obj.gz", "b2.obj.gz", "b3.obj.gz"}) write_gzip(dir / name, quad_obj);
  write_text(dir / "b2.obj.gz", bytes.substr(0, bytes.size() / 2));  // truncated
  write_text(dir / "s.xml", scene_with("<static name=\"body\" sequence=\"b#.obj.gz\"/>"));
  const CliResult r = run_cli("run " + (dir / "s.xml").string() + " --quiet");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("b2.obj.gz") != std::string::npos);
  CHECK(r.output.find("not a readable gzip file") != std::string::npos);
  CHECK(files_in(dir / "out").empty());
}

TEST_CASE("a missing sequence frame stops the run with exit code 2 naming that file") {
  const auto dir = scratch_dir("collider_missing_frame");
  write_text(dir / "b.0001.obj", tri_obj);
  write_text(dir / "b.0002.obj", tri_obj);
  write_text(dir / "s.xml", scene_with("<static name=\"body\" sequence=\"b.####.obj\"/>"));
  const CliResult r = run_cli("run " + (dir / "s.xml").string() + " --quiet");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("b.0003.obj") != std::string::npos);
  CHECK(r.output.find("missing") != std::string::npos);
  CHECK(files_in(dir / "out").empty());
}

TEST_CASE("a sequence frame with another vertex count stops the run with exit code 2 naming that file") {
  const auto dir = scratch_dir("collider_bad_frame");
  write_text(dir / "b.0001.obj", tri_obj);
  write_text(dir / "b.0002.obj", quad_obj);
  write_text(dir / "b.0003.obj", tri_obj);
  write_text(dir / "s.xml", scene_with("<static name=\"body\" sequence=\"b.####.obj\"/>"));
  const CliResult r = run_cli("run " + (dir / "s.xml").string() + " --quiet");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("b.0002.obj") != std::string::npos);
  CHECK(r.output.find("4 vertices") != std::string::npos);
}

TEST_CASE("collider elements: bad attributes are reported with the line and what was expected") {
  const auto dir = scratch_dir("collider_bad_attr");
  write_text(dir / "s.xml", scene_with("<sphere center=\"0 0 0\" radius=\"-1\"/>"));
  CliResult r = run_cli("validate " + (dir / "s.xml").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("s.xml:3") != std::string::npos);
  CHECK(r.output.find("radius") != std::string::npos);
  write_text(dir / "s.xml", scene_with("<plane point=\"0 0 0\" normal=\"0 0 0\"/>"));
  r = run_cli("validate " + (dir / "s.xml").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("normal") != std::string::npos);
  write_text(dir / "s.xml", scene_with("<static name=\"x\" obj=\"a.obj\" sequence=\"b.#.obj\"/>"));
  r = run_cli("validate " + (dir / "s.xml").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("exactly one of") != std::string::npos);
  write_text(dir / "s.xml", scene_with("<sphere radius=\"1\" normal=\"0 1 0\"/>"));
  r = run_cli("validate " + (dir / "s.xml").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("unknown attribute 'normal'") != std::string::npos);
}

TEST_CASE("animated collider: frames are interpolated linearly per step, velocities from the interpolation") {
  const auto dir = scratch_dir("collider_motion");
  write_rising_triangle(dir, 3, 0.24, 0);  // 0.24 m per frame at 24 fps: 5.76 m/s
  write_text(dir / "s.xml", scene_with("<static name=\"body\" sequence=\"b.####.obj\"/>"));
  auto sc = load_collision_scene(dir / "s.xml");
  const Model& m = sc.built.model;
  const SimOptions& o = sc.built.options;
  Workspace ws = make_workspace(m, o);
  // Step 5 of a frame of steps_per_frame steps starts at 5/steps_per_frame of the way to frame 2.
  sim::ColliderTrack(sc.desc).prepare(m, 2, ws.collision);
  place_colliders(m, 5 * o.dt, o.dt, ws.collision);
  const Real expected0 = 0.24 * 5 / o.steps_per_frame, expected1 = 0.24 * 6 / o.steps_per_frame;
  CHECK(ws.collision.collider_x0[0].y() == doctest::Approx(expected0));
  CHECK((ws.collision.collider_x1[2].y() - ws.collision.collider_x0[2].y()) / o.dt == doctest::Approx(5.76));
  CHECK(ws.collision.collider_x1[1].y() == doctest::Approx(expected1));
}

using clothsim::test::shared_data;

TEST_CASE("the real animated bodies (shared data, skipped without it): Kick and Rumba read as gzip, unpadded") {
  const auto data = shared_data();
  if (data.empty() || !std::filesystem::is_directory(data / "colliders" / "animated" / "cipc_kick")) {
    MESSAGE("shared data not found (../shared/data): skipped");
    return;
  }
  // data/MANIFEST.md: 12,811 vertices and 25,472 triangles in every frame; Kick's fastest frame step moves a
  // vertex 0.66 m (frame 70 to 71), Rumba's at most 8.3 cm. Frames 70..71 of each, read as a scene would.
  for (const auto& [name, fastest] : {std::pair{"cipc_kick", 0.66}, std::pair{"cipc_rumba", 0.0}}) {
    const auto dir = scratch_dir(std::string("collider_real_") + name);
    write_text(dir / "s.xml", "<scene>\n<simulation fps=\"25\" startFrame=\"70\" endFrame=\"71\"/>\n"
                              "<static name=\"body\" sequence=\"" +
                                  (data / "colliders" / "animated" / name / "shell#.obj.gz").string() +
                                  "\"/>\n<cloth name=\"c\" grid=\"3 3\"/>\n</scene>\n");
    const SceneDesc desc = io::read_scene((dir / "s.xml").string());
    const auto meshes = io::read_colliders(desc);
    REQUIRE(meshes[0].frame_count == 2);
    const MeshData a = io::read_collider_frame(desc, 0, 70), b = io::read_collider_frame(desc, 0, 71);
    CHECK(a.positions == meshes[0].mesh->positions);
    CHECK(a.vertex_count() == 12811);
    CHECK(a.triangle_count() == 25472);
    CHECK(a.tri_index == b.tri_index);
    Real most = 0;
    for (Index i = 0; i < a.vertex_count(); ++i) most = std::max(most, (b.positions[i] - a.positions[i]).norm());
    if (fastest > 0) CHECK(most == doctest::Approx(fastest).epsilon(0.01));
    else CHECK(most < 0.083);
  }
}
