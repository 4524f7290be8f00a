// The clothsim binary end to end: frames written and readable, stats, thread-count determinism, examples.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>

#include "io/obj_reader.h"
#include "tests/support/cli_harness.h"

using namespace clothsim;
using namespace clothsim::test;
namespace fs = std::filesystem;

namespace {

// A sheet with every force switched on, so determinism covers springs, wind (normals) and random forces.
const char* busy_scene = R"(<scene>
  <simulation timestep="0.0005" fps="25" startFrame="1" endFrame="6" integrator="INTEGRATOR"/>
  <forces>
    <external acceleration="0.1 0 0"/>
    <wind velocity="3 0 2" strength="1"/>
    <random amplitude="2" seed="5" negY="false"/>
    <airDamping value="0.05"/>
  </forces>
  <cloth name="sheet" grid="20 20" size="1 1" translate="0 1 0" rotate="10 0 5" saveName="sheet">
    <density value="0.2"/><stiffness value="5" bend="0.2"/><damping value="0.05"/>
    <pins vertices="0 19"/>
  </cloth>
</scene>)";

std::string scene_with(const std::string& integrator) {
  std::string s = busy_scene;
  s.replace(s.find("INTEGRATOR"), 10, integrator);
  return s;
}

}  // namespace

TEST_CASE("run writes one whole OBJ per frame with v, vt, vn and f lines that read back to 9 digits") {
  const fs::path dir = scratch_dir("run_frames");
  write_text(dir / "scene.xml", scene_with("symplectic"));
  const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --out " + (dir / "out").string() +
                              " --stats " + (dir / "stats.json").string() + " --quiet");
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.empty());  // --quiet
  const auto files = files_in(dir / "out");
  REQUIRE(files.size() == 6);
  CHECK(files.front() == "sheet.0001.obj");
  CHECK(files.back() == "sheet.0006.obj");
  const std::string text = read_text(dir / "out" / "sheet.0006.obj");
  std::size_t v = 0, vt = 0, vn = 0, f = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    v += line.rfind("v ", 0) == 0;
    vt += line.rfind("vt ", 0) == 0;
    vn += line.rfind("vn ", 0) == 0;
    f += line.rfind("f ", 0) == 0;
  }
  CHECK(v == 400);
  CHECK(vt == 400);
  CHECK(vn == 400);
  CHECK(f == 2 * 19 * 19);
  // Another OBJ reader (tinyobjloader, through io::read_obj) sees the same mesh.
  const MeshData back = io::read_obj((dir / "out" / "sheet.0006.obj").string());
  CHECK(back.vertex_count() == 400);
  CHECK(back.triangle_count() == 2 * 19 * 19);
  CHECK(back.uvs.size() == 400);
  // Frame 1 is the initial state: the pinned corner 0 sits at the transformed grid corner, and stays there.
  const MeshData first = io::read_obj((dir / "out" / "sheet.0001.obj").string());
  CHECK((back.positions[0] - first.positions[0]).norm() == 0);
  CHECK(back.positions[20].y() < first.positions[20].y());  // the rest has fallen
  const std::string stats = read_text(dir / "stats.json");
  for (const char* key : {"\"particles\":400", "\"triangles\":722", "\"springs\":{", "\"structural\":760",
                          "\"shear\":722", "\"flex\":720", "\"steps\":400", "\"wall_seconds\"", "\"phases\":{",
                          "\"load\"", "\"topology\"", "\"forces\"", "\"integrate\"", "\"write\"", "\"phases_cpu\":{",
                          "\"peak_rss_bytes\"", "\"frames\":[", "\"max_strain\"", "\"kinetic_energy\""})
    CHECK_MESSAGE(stats.find(key) != std::string::npos, key);
}

TEST_CASE("the same scene gives byte-identical frames at 1 and 2 threads, for every integrator") {
  for (const char* integrator : {"euler", "symplectic", "rk4"}) {
    CAPTURE(integrator);
    const fs::path dir = scratch_dir(std::string("threads_") + integrator);
    write_text(dir / "scene.xml", scene_with(integrator));
    for (const char* n : {"1", "2"})
      REQUIRE(run_cli("run " + (dir / "scene.xml").string() + " --quiet --threads " + n + " --out " +
                      (dir / n).string()).exit_code == 0);
    const auto files = files_in(dir / "1");
    REQUIRE(files.size() == 6);
    CHECK(files == files_in(dir / "2"));
    for (const std::string& f : files) CHECK(read_text(dir / "1" / f) == read_text(dir / "2" / f));
    CHECK(read_text(dir / "1" / files.back()) != read_text(dir / "1" / files.front()));  // it did move
  }
}

TEST_CASE("--frames A:B writes only those frames, equal to the same frames of a full run") {
  const fs::path dir = scratch_dir("frames_range");
  write_text(dir / "scene.xml", scene_with("rk4"));
  REQUIRE(run_cli("run " + (dir / "scene.xml").string() + " --quiet --out " + (dir / "all").string()).exit_code == 0);
  REQUIRE(run_cli("run " + (dir / "scene.xml").string() + " --quiet --frames 3:4 --out " + (dir / "part").string())
              .exit_code == 0);
  CHECK(files_in(dir / "part") == std::vector<std::string>{"sheet.0003.obj", "sheet.0004.obj"});
  CHECK(read_text(dir / "part" / "sheet.0004.obj") == read_text(dir / "all" / "sheet.0004.obj"));
}

TEST_CASE("progress: one line per frame when stderr is not a terminal") {
  const fs::path dir = scratch_dir("progress");
  write_text(dir / "scene.xml", scene_with("symplectic"));
  const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --out " + (dir / "out").string());
  REQUIRE(r.exit_code == 0);
  CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 6);
  CHECK(r.output.find("frame 0006  6/6") != std::string::npos);
}

TEST_CASE("every bundled example runs and writes its frames" * doctest::test_suite("slow")) {
  for (const char* scene : {"flag/flag.xml", "hanging_sheet/sheet.xml", "pieces/pieces.xml", "two_sheets/two_sheets.xml"}) {
    CAPTURE(scene);
    const fs::path dir = scratch_dir(std::string("example_") + fs::path(scene).stem().string());
    const CliResult r = run_cli("run " + std::string(CLOTHSIM_SOURCE_DIR) + "/examples/" + scene + " --quiet --out " +
                                dir.string() + " --stats " + (dir / "stats.json").string());
    CHECK(r.exit_code == 0);
    CHECK(files_in(dir).size() > 40);
    CHECK(read_text(dir / "stats.json").find("\"status\":\"ok\"") != std::string::npos);
  }
}

TEST_CASE("info reports hand-counted figures for a quad of two triangles") {
  const fs::path dir = scratch_dir("info");
  write_text(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const CliResult r = run_cli("info " + (dir / "quad.obj").string() + " --json");
  REQUIRE(r.exit_code == 0);
  for (const char* key : {"\"vertices\":4", "\"triangles\":2", "\"edges\":5", "\"edge_springs\":5",
                          "\"bend_springs\":1", "\"pieces\":1", "\"boundary_edges\":4", "\"nonmanifold_edges\":0",
                          "\"degenerate_triangles\":0", "\"load_seconds\"", "\"topology_seconds\""})
    CHECK_MESSAGE(r.output.find(key) != std::string::npos, key);
}

TEST_CASE("validate checks a scene without simulating, --help works, unknown options are errors") {
  const fs::path dir = scratch_dir("validate");
  write_text(dir / "scene.xml", scene_with("rk4"));
  const CliResult ok = run_cli("validate " + (dir / "scene.xml").string());
  CHECK(ok.exit_code == 0);
  CHECK(ok.output.find("particles 400") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out"));
  for (const char* cmd : {"run", "validate", "info"}) {
    const CliResult h = run_cli(std::string(cmd) + " --help");
    CHECK(h.exit_code == 0);
    CHECK(h.output.find("usage: clothsim") != std::string::npos);
  }
  const CliResult bad = run_cli("run " + (dir / "scene.xml").string() + " --thread 2");
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find("unknown option '--thread'") != std::string::npos);
}

TEST_CASE("validate warns on undamped explicit Euler and on colliders with collisionIterations 0") {
  const fs::path dir = scratch_dir("validate_warnings");
  auto validate = [&](const std::string& sim, const std::string& damping, bool collider) {
    write_text(dir / "s.xml", "<scene><simulation timestep=\"0.0001\" " + sim + "/>" +
                                  (collider ? "<plane name=\"ground\"/>" : "") +
                                  "<cloth name=\"c\" grid=\"4 4\" translate=\"0 1 0\"><damping value=\"" + damping +
                                  "\"/></cloth></scene>");
    const CliResult r = run_cli("validate " + (dir / "s.xml").string());
    CHECK(r.exit_code == 0);
    return r.output;
  };
  const std::string euler = "integrator=\"euler\" without damping";
  const std::string off = "collisionIterations=\"0\" turns collisions off: the 1 collider will be ignored";
  CHECK(validate("integrator=\"euler\"", "0", false).find(euler) != std::string::npos);
  CHECK(validate("integrator=\"euler\"", "0.1", false).find(euler) == std::string::npos);
  CHECK(validate("integrator=\"symplectic\"", "0", false).find(euler) == std::string::npos);
  CHECK(validate("collisionIterations=\"0\"", "0.1", true).find(off) != std::string::npos);
  CHECK(validate("collisionIterations=\"0\"", "0.1", false).find(off) == std::string::npos);
  CHECK(validate("collisionIterations=\"1\"", "0.1", true).find(off) == std::string::npos);
}

TEST_CASE("an implicit scene of three cloths: three Cholesky pieces in --stats, and the same bytes at 1 and 2 threads") {
  // Two 24 x 24 sheets (576 particles: a piece each) and an 8 x 8 one (64: gathered, alone, into a third).
  std::string scene = R"(<scene>
  <simulation timestep="0.01" fps="25" startFrame="1" endFrame="4" integrator="implicit" preconditioner="cholesky"/>)";
  const char* sheets[3][2] = {{"24 24", "0 1 0"}, {"8 8", "2 1 0"}, {"24 24", "4 1 0"}};
  for (int k = 0; k < 3; ++k)
    scene += std::string(R"(
  <cloth name="s)") + std::to_string(k) + R"(" grid=")" + sheets[k][0] + R"(" size="1 1" translate=")" + sheets[k][1] +
             R"(" saveName="s)" + std::to_string(k) + R"(">
    <density value="0.2"/><stiffness value="1000" bend="0.1"/><damping value="0.1"/><pins vertices="0"/>
  </cloth>)";
  scene += "\n</scene>\n";
  const fs::path dir = scratch_dir("cholesky_pieces");
  write_text(dir / "scene.xml", scene);
  for (const char* n : {"1", "2"})
    REQUIRE(run_cli("run " + (dir / "scene.xml").string() + " --quiet --threads " + n + " --out " + (dir / n).string() +
                    " --stats " + (dir / n).string() + ".json").exit_code == 0);
  CHECK(read_text(dir / "2.json").find("\"cholesky_pieces\":3") != std::string::npos);
  const auto files = files_in(dir / "1");
  REQUIRE(files.size() == 12);
  CHECK(files == files_in(dir / "2"));
  for (const std::string& f : files) CHECK(read_text(dir / "1" / f) == read_text(dir / "2" / f));
  CHECK(read_text(dir / "1" / "s2.0004.obj") != read_text(dir / "1" / "s2.0001.obj"));  // it did move
}
