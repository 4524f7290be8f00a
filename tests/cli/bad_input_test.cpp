// Every bad input stops with exit code 2, one message naming the file, the line where known and what was
// expected, and no output file.
#include <doctest/doctest.h>
#include <sys/stat.h>

#include <filesystem>

#include "tests/support/cli_harness.h"

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

// The command killed after 20 s (exit code 137): a FIFO nobody writes to blocks its reader for ever, and a
// hang must fail the test, not stop the suite.
CliResult run_cli_bounded(const std::string& args) {
  CliResult r;
  FILE* p = popen(("timeout -s KILL 20 " + std::string(CLOTHSIM_BIN) + " " + args + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  for (std::size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) r.output.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

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
      {"bad bending", scene_text(sim, obj_cloth + " bending=\"hinges\"", ""), good_obj, "scene.xml:3",
       "attribute bending=\"hinges\"; expected springs or dihedral"},
      {"negative bend modulus", scene_text(sim, obj_cloth + " bending=\"dihedral\"",
       "    <stiffness bendModulus=\"-1e-5\"/>\n"), good_obj, "scene.xml:4", "expected a number >= 0 (N m)"},
      {"bend modulus on springs", scene_text(sim, obj_cloth, "    <stiffness bendModulus=\"1e-5\"/>\n"), good_obj,
       "scene.xml:4", "bendModulus applies to <cloth bending=\"dihedral\">"},
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
      // Hostile but realistic input: each of these was once accepted or reported unclearly.
      {"duplicate attribute", scene_text(sim + " fps=\"30\"", obj_cloth, ""), good_obj, "scene.xml:2",
       "attribute 'fps' appears twice"},
      {"two forces", "<scene>\n<simulation/>\n<forces/>\n<forces/>\n<cloth " + obj_cloth + "/>\n</scene>\n", good_obj,
       "scene.xml:4", "appears twice; expected one <forces>"},
      {"two air dampings", "<scene>\n<forces>\n<airDamping value=\"1\"/>\n<airDamping value=\"2\"/>\n</forces>\n<cloth " +
       obj_cloth + "/>\n</scene>\n", good_obj, "scene.xml:4", "appears twice in <forces>"},
      {"two densities", scene_text(sim, obj_cloth, "    <density value=\"1\"/>\n    <density value=\"2\"/>\n"), good_obj,
       "scene.xml:5", "appears twice in <cloth>"},
      {"second root", scene_text(sim, obj_cloth, "") + "<scene/>\n", good_obj, "scene.xml:6", "a second root element"},
      {"second simulation with attributes", "<scene>\n<simulation/>\n<simulation fps=\"30\"/>\n<cloth " + obj_cloth +
       "/>\n</scene>\n", good_obj, "scene.xml:3", "appears twice; expected one <simulation>"},
      {"namespace on scene", "<scene xmlns=\"http://example.org\">\n<cloth " + obj_cloth + "/>\n</scene>\n", good_obj,
       "scene.xml:1", "unknown attribute 'xmlns'; expected no attributes"},
      {"newline in name", scene_text(sim, obj_cloth + " name=\"a&#10;v 9 9 9\"", ""), good_obj, "scene.xml:3",
       "attribute name holds control character 10 at position 2; expected a name without control characters"},
      {"newline in texture", scene_text(sim, obj_cloth + " texture=\"t.png&#10;Kd 1 0 0\"", ""), good_obj,
       "scene.xml:3",
       "attribute texture holds control character 10 at position 6"},
      {"empty saveDir", scene_text(sim, "obj=\"mesh.obj\" saveDir=\"\"", ""), good_obj, "scene.xml:3",
       "attribute saveDir=\"\"; expected a folder path"},
      {"same output spelt twice", "<scene>\n<cloth obj=\"mesh.obj\" saveDir=\"d1\" saveName=\"c\"/>\n"
       "<cloth obj=\"mesh.obj\" saveDir=\"./d1/\" saveName=\"c\"/>\n</scene>\n", good_obj, "scene.xml:3",
       "writes to the same files as another"},
      {"steps past the limit", scene_text("timestep=\"1e-11\"", obj_cloth, ""), good_obj, "scene.xml:2",
       "needs more than 1000000 steps a frame"},
      {"tiny fps", scene_text("fps=\"1e-9\"", obj_cloth, ""), good_obj, "scene.xml:2",
       "needs more than 1000000 steps a frame"},
      {"huge scale", scene_text(sim, obj_cloth + " scale=\"1e300\"", ""), good_obj, "scene.xml:3",
       "of magnitude at most 1e12"},
      {"huge stiffness", scene_text(sim, obj_cloth, "    <stiffness value=\"1e308\"/>\n"), good_obj, "scene.xml:4",
       "of magnitude at most 1e12"},
      {"huge coordinate", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n", "mesh.obj:2",
       "of magnitude at most 1e12"},
      {"folder as mesh", scene_text(sim, "obj=\".\" saveDir=\"out\"", ""), good_obj, "",
       "is a folder, not a regular file; expected an OBJ mesh"},
      {"device as map", scene_text(sim, obj_cloth, "    <stiffness min=\"1\" max=\"2\" map=\"/dev/zero\"/>\n"),
       "v 0 0 0\nv 1 0 0\nv 1 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n", "scene.xml:4", "is a character device"},
      {"face index wraps", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 4294967299\n", "mesh.obj:6",
       "face corner '4294967299': bad index '4294967299'; expected a non-zero integer"},
      {"face index with letters", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 4abc\n", "mesh.obj:6",
       "face corner '4abc': bad index '4abc'"},
      {"face index with a point", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 3.7\n", "mesh.obj:6", "face corner '3.7': bad index '3.7'"},
      {"face uv index with letters", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 4/abc\n", "mesh.obj:6", "face corner '4/abc': bad index 'abc'"},
      {"face index zero", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 0\n", "mesh.obj:6", "face corner '0': bad index '0'"},
      {"face line continuation", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 4 \\\n", "mesh.obj:6",
       "face corner '\\': a line continuation; expected the whole face on one line"},
      {"face inline comment", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 4 # comment\n", "mesh.obj:6",
       "face corner '#': a comment after a face; expected comments on lines of their own"},
      {"face corner of four indices", scene_text(sim, obj_cloth, ""), "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 1/1/1/1\n", "mesh.obj:6",
       "face corner '1/1/1/1': more than three indices"},
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

TEST_CASE("a FIFO or a device or a folder as an input is refused at once and never read") {
  const fs::path dir = scratch_dir("bad_special_inputs");
  REQUIRE(::mkfifo((dir / "fifo.obj").c_str(), 0600) == 0);
  REQUIRE(::mkfifo((dir / "fifo.xml").c_str(), 0600) == 0);
  write_text(dir / "scene.xml", "<scene><cloth obj=\"fifo.obj\" saveDir=\"out\"/></scene>\n");
  const CliResult obj = run_cli_bounded("run " + (dir / "scene.xml").string() + " --quiet");
  CHECK(obj.exit_code == 2);
  CHECK(obj.output.find("fifo.obj: is a FIFO (named pipe), not a regular file; expected an OBJ mesh") != std::string::npos);
  const CliResult scene = run_cli_bounded("run " + (dir / "fifo.xml").string() + " --quiet");
  CHECK(scene.exit_code == 2);
  CHECK(scene.output.find("fifo.xml: is a FIFO (named pipe), not a regular file") != std::string::npos);
  const CliResult folder = run_cli_bounded("validate " + dir.string());
  CHECK(folder.exit_code == 2);
  CHECK(folder.output.find("is a folder, not a regular file; expected a scene XML file") != std::string::npos);
  // /dev/zero never ends: as a batch list it grew memory without bound.
  const CliResult list = run_cli_bounded("batch /dev/zero --out " + (dir / "batch").string());
  CHECK(list.exit_code == 2);
  CHECK(list.output.find("/dev/zero: is a character device") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out"));
}

TEST_CASE("a collider frame with a re-wound triangle is named as such and not by equal counts") {
  const fs::path dir = scratch_dir("bad_rewound_collider");
  write_text(dir / "body.0001.obj", "v 0 -1 0\nv 1 -1 0\nv 0 -1 1\nv 1 -1 1\nf 1 2 3\nf 2 4 3\n");
  write_text(dir / "body.0002.obj", "v 0 -1 0\nv 1 -1 0\nv 0 -1 1\nv 1 -1 1\nf 1 2 3\nf 2 3 4\n");
  write_text(dir / "scene.xml", "<scene><simulation startFrame=\"1\" endFrame=\"2\"/><static sequence=\"body.####.obj\"/>"
                                "<cloth grid=\"2 2\" saveDir=\"out\"/></scene>\n");
  const CliResult r = run_cli("validate " + (dir / "scene.xml").string());
  CHECK(r.exit_code == 2);
  CHECK_MESSAGE(r.output.find("body.0002.obj: collider 'static0': triangle 2 has other corners (or another winding) "
                              "than in " + (dir / "body.0001.obj").string()) != std::string::npos, r.output);
}

TEST_CASE("a divergence at a step already below the stability limit does not advise a smaller step") {
  const fs::path dir = scratch_dir("bad_inside_sphere");
  // A cloth starting inside a sphere, at 0.2 ms: below half the damped symplectic limit of these springs
  // (0.799 ms, docs/stability.md).
  write_text(dir / "scene.xml", "<scene><simulation timestep=\"0.0002\" fps=\"25\" startFrame=\"1\" endFrame=\"3\"/>"
                                "<sphere center=\"0 0 0\" radius=\"0.5\"/>"
                                "<cloth grid=\"8 8\" size=\"1 1\" saveDir=\"out\" saveName=\"c\"/></scene>\n");
  const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet");
  CHECK(r.exit_code == 3);
  CHECK_MESSAGE(r.output.find("The step was 0.0002 s: the step is already below half the stability limit 0.000799 s") !=
                    std::string::npos, r.output);
  CHECK(r.output.find("use a time step below") == std::string::npos);
}
