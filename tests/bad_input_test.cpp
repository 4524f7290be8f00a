// Every bad input stops with exit code 2, one message naming the file, the line where known and what was
// expected, and no output file.
#include <doctest/doctest.h>

#include <filesystem>

#include "cli_harness.h"

using namespace clothsim::test;
namespace fs = std::filesystem;

namespace {

const char* good_obj = "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 4\n";

std::string scene_text(const std::string& simulation, const std::string& cloth_attrs, const std::string& inner) {
  return "<scene>\n  <simulation " + simulation + "/>\n  <cloth " + cloth_attrs + ">\n" + inner + "  </cloth>\n</scene>\n";
}

struct Case {
  const char* name;
  std::string scene;     // scene.xml contents ("" = do not write it)
  std::string obj;       // mesh.obj contents ("" = do not write it)
  std::string where;     // expected "file:line" fragment (file relative to the case folder)
  std::string expected;  // expected words of the message
};

}  // namespace

TEST_CASE("bad input: exit code 2, file, line and expectation in the message, no output file") {
  const std::string sim = "timestep=\"0.01\" fps=\"25\" startFrame=\"1\" endFrame=\"3\"";
  const std::string obj_cloth = "obj=\"mesh.obj\" saveDir=\"out\"";
  const std::vector<Case> cases = {
      {"missing scene", "", good_obj, "scene.xml", "cannot read file"},
      {"missing mesh", scene_text(sim, "obj=\"nope.obj\" saveDir=\"out\"", ""), "", "nope.obj", "expected an OBJ mesh"},
      {"malformed xml", "<scene>\n<simulation timestep=\"0.01\">\n</scene>\n", good_obj, "scene.xml:3", "malformed XML"},
      {"unknown element", scene_text(sim, obj_cloth, "    <stifness value=\"3\"/>\n"), good_obj, "scene.xml:4",
       "unknown element in <cloth>"},
      {"unknown attribute", scene_text(sim + " timestpe=\"1\"", obj_cloth, ""), good_obj, "scene.xml:2",
       "unknown attribute 'timestpe'"},
      {"zero density", scene_text(sim, obj_cloth, "    <density value=\"0\"/>\n"), good_obj, "scene.xml:4",
       "expected a positive number (kg/m^2)"},
      {"negative thickness", scene_text(sim, obj_cloth, "    <thickness value=\"-1\"/>\n"), good_obj, "scene.xml:4",
       "expected a positive number (m)"},
      {"zero time step", scene_text("timestep=\"0\"", obj_cloth, ""), good_obj, "scene.xml:2",
       "expected a positive number (s)"},
      {"not a number", scene_text("timestep=\"fast\"", obj_cloth, ""), good_obj, "scene.xml:2",
       "expected a positive number (s)"},
      {"start after end", scene_text("startFrame=\"9\" endFrame=\"3\"", obj_cloth, ""), good_obj, "scene.xml:2",
       "expected startFrame <= endFrame"},
      {"bad integrator", scene_text("integrator=\"verlet\"", obj_cloth, ""), good_obj, "scene.xml:2",
       "one of euler, symplectic, rk4"},
      {"pin out of range", scene_text(sim, obj_cloth, "    <pins vertices=\"0 4\"/>\n"), good_obj, "scene.xml:3",
       "pinned vertex 4 is out of range"},
      {"no faces", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "mesh.obj", "no faces"},
      {"nan coordinate", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "mesh.obj:2",
       "expected a finite number"},
      {"infinite coordinate", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", "mesh.obj:3",
       "expected a finite number"},
      {"index out of range", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n",
       "mesh.obj:5", "out of range"},
      {"zero-length edge", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\nf 2 3 4\n",
       "mesh.obj:6", "zero-length edge"},
      {"zero-area triangle", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\n",
       "mesh.obj:6", "zero-area triangle"},
      {"unwritable output", scene_text(sim, "obj=\"mesh.obj\" saveDir=\"blocker/out\"", ""), good_obj, "blocker/out",
       "cannot create output folder"},
  };
  for (const Case& c : cases) {
    const std::string name = c.name;
    CAPTURE(name);
    std::string folder = "bad_" + name;
    std::replace(folder.begin(), folder.end(), ' ', '_');
    const fs::path dir = scratch_dir(folder);
    if (!c.scene.empty()) write_text(dir / "scene.xml", c.scene);
    if (!c.obj.empty()) write_text(dir / "mesh.obj", c.obj);
    write_text(dir / "blocker", "a file where a folder is expected\n");
    const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet");
    CHECK(r.exit_code == 2);
    CHECK_MESSAGE(r.output.find((dir / c.where).string()) != std::string::npos, r.output);
    CHECK_MESSAGE(r.output.find(c.expected) != std::string::npos, r.output);
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);  // one message
    CHECK_FALSE(fs::exists(dir / "out"));
    // validate reports the same problem without simulating (except the output folder, which run creates).
    if (std::string(c.name) != "unwritable output") {
      const CliResult v = run_cli("validate " + (dir / "scene.xml").string());
      CHECK(v.exit_code == 2);
      CHECK(v.output.find(c.expected) != std::string::npos);
    }
  }
}

TEST_CASE("polygons are split into triangles with their count reported, a bad OBJ never crashes info") {
  const fs::path dir = scratch_dir("bad_info");
  write_text(dir / "pent.obj", "v 0 0 0\nv 1 0 0\nv 1.5 1 0\nv 0.5 1.5 0\nv -0.5 1 0\nf 1 2 3 4 5\n");
  const CliResult r = run_cli("info " + (dir / "pent.obj").string() + " --json");
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("\"triangles\":3") != std::string::npos);
  CHECK(r.output.find("\"polygons_triangulated\":1") != std::string::npos);
  write_text(dir / "garbage.obj", "v 1 2\nf 1 2 3\n");
  const CliResult g = run_cli("info " + (dir / "garbage.obj").string());
  CHECK(g.exit_code == 2);
  CHECK(g.output.find("garbage.obj:1") != std::string::npos);
}
