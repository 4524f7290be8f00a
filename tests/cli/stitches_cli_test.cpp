// Sewing records in a cloth OBJ and in the scene: counted by info and validate; a bad one stops with exit code 2
// and file:line.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include "io/obj_reader.h"
#include "tests/support/cli_harness.h"

using namespace clothsim;
using namespace clothsim::test;
namespace fs = std::filesystem;

namespace {

// Two separate triangles (pieces) side by side, 1 mm apart along x; vertices 1 and 2 of the first face vertices
// 3 and 5 of the second.
const char* two_panels =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 1.001 0 0\nv 2 0 0\nv 1.001 1 0\n"
    "f 1 2 3\nf 4 5 6\n";

std::string scene(const std::string& cloth_attrs, const std::string& inner) {
  return "<scene>\n  <simulation timestep=\"0.01\" fps=\"25\" startFrame=\"1\" endFrame=\"1\"/>\n"
         "  <cloth obj=\"mesh.obj\" saveDir=\"out\" " + cloth_attrs + ">\n" + inner + "  </cloth>\n</scene>\n";
}

}  // namespace

TEST_CASE("stitch records: 0-based, read with their weight and info counts stitches and seams") {
  const fs::path dir = scratch_dir("stitch_info");
  write_text(dir / "mesh.obj", std::string(two_panels) + "seam 2\nstitch 3 1 2 0.25\nstitch 5 2 2 0\n");
  const MeshData mesh = io::read_obj((dir / "mesh.obj").string());
  REQUIRE(mesh.stitch_count() == 2);
  CHECK(mesh.seam_count == 1);
  CHECK(mesh.stitch_a[0] == 3);
  CHECK(mesh.stitch_b[0] == 1);
  CHECK(mesh.stitch_c[0] == 2);
  CHECK(mesh.stitch_w[0] == 0.25);
  CHECK(mesh.stitch_w[1] == 0);
  const CliResult r = run_cli("info " + (dir / "mesh.obj").string() + " --json");
  CHECK(r.exit_code == 0);
  CHECK_MESSAGE(r.output.find("\"stitches\":2") != std::string::npos, r.output);
  CHECK(r.output.find("\"seams\":1") != std::string::npos);
  write_text(dir / "scene.xml", scene("", "    <stitch vertices=\"0 3\"/>\n"));
  const CliResult v = run_cli("validate " + (dir / "scene.xml").string());
  CHECK(v.exit_code == 0);
  CHECK_MESSAGE(v.output.find("stitches 3") != std::string::npos, v.output);  // 2 records + 1 scene pair
}

TEST_CASE("weld sews boundary vertices of different pieces closer than the distance, each pair once") {
  const fs::path dir = scratch_dir("stitch_weld");
  write_text(dir / "mesh.obj", two_panels);
  // 1 mm apart: vertices 1-3 and 2-5 (0-based) are the two close pairs.
  write_text(dir / "scene.xml", scene("weld=\"0.0015\"", ""));
  const CliResult v = run_cli("validate " + (dir / "scene.xml").string());
  CHECK(v.exit_code == 0);
  CHECK_MESSAGE(v.output.find("stitches 2") != std::string::npos, v.output);
  write_text(dir / "scene.xml", scene("weld=\"0.0005\"", ""));
  CHECK(run_cli("validate " + (dir / "scene.xml").string()).output.find("stitches 0") != std::string::npos);
}

TEST_CASE("bad stitches: exit code 2 with file:line") {
  struct Case {
    const char* name;
    std::string obj, scene, where, expected;
  };
  const std::string plain = scene("", "");
  const std::vector<Case> cases = {
      {"index out of range", std::string(two_panels) + "stitch 0 1 6 0.5\n", plain, "mesh.obj:9", "out of range"},
      {"negative index", std::string(two_panels) + "stitch -1 1 2 0.5\n", plain, "mesh.obj:9", "out of range"},
      {"weight above 1", std::string(two_panels) + "stitch 3 1 2 1.5\n", plain, "mesh.obj:9", "outside [0, 1]"},
      {"weight not a number", std::string(two_panels) + "stitch 3 1 2 nan\n", plain, "mesh.obj:9", "bad stitch weight"},
      {"missing weight", std::string(two_panels) + "stitch 3 1 2\n", plain, "mesh.obj:9", "bad stitch weight"},
      {"scene pair out of range", two_panels, scene("", "    <stitch vertices=\"0 6\"/>\n"), "scene.xml:3",
       "out of range"},
      {"scene odd count", two_panels, scene("", "    <stitch vertices=\"0 3 4\"/>\n"), "scene.xml:4", "vertex pairs"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    std::string folder = std::string("bad_stitch_") + c.name;
    std::replace(folder.begin(), folder.end(), ' ', '_');
    const fs::path dir = scratch_dir(folder);
    write_text(dir / "mesh.obj", c.obj);
    write_text(dir / "scene.xml", c.scene);
    const CliResult r = run_cli("validate " + (dir / "scene.xml").string());
    CHECK(r.exit_code == 2);
    CHECK_MESSAGE(r.output.find((dir / c.where).string()) != std::string::npos, r.output);
    CHECK_MESSAGE(r.output.find(c.expected) != std::string::npos, r.output);
  }
}
