// Maps through the whole program: pins maps, a constant map against its scalar, several cloths in one
// scene, the colour texture's material, and every bad map input answered with exit code 2.
#include <doctest/doctest.h>

#include <filesystem>
#include <sstream>

#include "tests/support/cli_harness.h"
#include "tests/support/png_fixtures.h"

using namespace clothsim::test;

namespace {

// The "v" lines of an OBJ frame, as written.
std::vector<std::string> vertex_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("v ", 0) == 0) out.push_back(line);
  return out;
}

std::string frame_name(const std::string& save_name, int frame) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s.%04d.obj", save_name.c_str(), frame);
  return buf;
}

const char* simulation = R"(<simulation timestep="0.001" fps="24" startFrame="1" endFrame="6"/>)";

}  // namespace

TEST_CASE("a pins map pins exactly the vertices over white, and they stay put for the whole run") {
  const auto dir = scratch_dir("maps_pins");
  // 10 x 10 texels, the three left columns white. Grid vertex column i sits at u = i/10, i.e. x = i - 0.5 in
  // texels: columns 0..2 read white (1), column 3 reads half grey (0.5, not above it), the rest black.
  std::vector<std::uint16_t> px;
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 10; ++i) px.push_back(i < 3 ? 255 : 0);
  write_png(dir / "pins.png", 10, 10, 1, 8, px);
  write_text(dir / "scene.xml", std::string("<scene>") + simulation +
                                    R"(<cloth name="sheet" grid="11 11" saveDir="out"><stiffness value="100"/><pins map="pins.png"/></cloth></scene>)");
  const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet");
  REQUIRE_MESSAGE(r.exit_code == 0, r.output);
  const auto first = vertex_lines(read_text(dir / "out" / frame_name("sheet", 1)));
  REQUIRE(first.size() == 121);
  int pinned = 0;
  for (int frame = 2; frame <= 6; ++frame) {
    const auto now = vertex_lines(read_text(dir / "out" / frame_name("sheet", frame)));
    REQUIRE(now.size() == 121);
    pinned = 0;
    for (int v = 0; v < 121; ++v) {
      const bool over_white = v % 11 <= 2;
      if (over_white) CHECK(now[v] == first[v]);  // not a digit moved
      else CHECK(now[v] != first[v]);             // everything else falls
      pinned += now[v] == first[v];
    }
  }
  CHECK(pinned == 33);  // 3 columns of 11
}

TEST_CASE("constant maps and the same scalar values give byte-identical frames") {
  const auto dir = scratch_dir("maps_constant");
  write_constant_png(dir / "white.png", 8, 8, 255);
  // A white map gives max exactly (lerp is exact at its ends), so each mapped value equals the scalar.
  const std::string scalar = R"(<density value="0.3"/><stiffness value="250" bend="0.5"/><damping value="0.02"/>
      <thickness value="0.004"/>)";
  const std::string mapped = R"(<density min="0.1" max="0.3" map="white.png"/>
      <stiffness min="10" max="250" map="white.png" bend="0.5"/><damping min="0" max="0.02" map="white.png"/>
      <thickness min="0.001" max="0.004" map="white.png"/>)";
  for (const auto& [name, params] : {std::pair{"scalar", scalar}, std::pair{"mapped", mapped}})
    write_text(dir / (std::string(name) + ".xml"),
               std::string("<scene>") + simulation + R"(<cloth name="sheet" grid="9 7" rotate="30 0 0" saveDir=")" +
                   name + R"(">)" + params + R"(<pins vertices="0 8"/></cloth></scene>)");
  for (const char* name : {"scalar", "mapped"}) {
    const CliResult r = run_cli("run " + (dir / (std::string(name) + ".xml")).string() + " --quiet");
    REQUIRE_MESSAGE(r.exit_code == 0, r.output);
  }
  REQUIRE(files_in(dir / "scalar").size() == 6);
  CHECK(files_in(dir / "scalar") == files_in(dir / "mapped"));
  for (const std::string& f : files_in(dir / "scalar")) {
    INFO(f);
    CHECK(read_text(dir / "scalar" / f) == read_text(dir / "mapped" / f));
  }
  // The frames did change over the run, so the comparison compared motion, not just the rest pose.
  CHECK(read_text(dir / "scalar" / frame_name("sheet", 1)) != read_text(dir / "scalar" / frame_name("sheet", 6)));
}

TEST_CASE("several cloths in one scene: each its own mesh, maps, output name and folder, same bytes at 1 and 2 threads") {
  const auto dir = scratch_dir("maps_many");
  std::vector<std::uint16_t> ramp;
  for (int i = 0; i < 16; ++i) ramp.push_back(std::uint16_t(17 * i));
  write_png(dir / "ramp.png", 16, 1, 1, 8, ramp);
  write_text(dir / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nf 1/1 2/2 4/4\nf 1/1 4/4 3/3\n");
  write_text(dir / "scene.xml", std::string("<scene>") + simulation + R"(
    <cloth name="a" grid="6 5" saveDir="out_a" saveName="first"><stiffness min="50" max="500" map="ramp.png"/>
      <pins map="ramp.png"/></cloth>
    <cloth name="b" obj="tri.obj" translate="3 0 0" saveDir="out_b" saveName="second" texture="ramp.png">
      <mass value="0.01"/><damping min="0" max="0.1" map="ramp.png"/><pins vertices="2 3"/></cloth>
  </scene>)");
  for (const char* threads : {"1", "2"}) {
    const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet --threads " + threads);
    REQUIRE_MESSAGE(r.exit_code == 0, r.output);
    std::filesystem::rename(dir / "out_a", dir / (std::string("a") + threads));
    std::filesystem::rename(dir / "out_b", dir / (std::string("b") + threads));
  }
  CHECK(files_in(dir / "a1").size() == 6);
  CHECK(files_in(dir / "b1").size() == 7);  // six frames and second.mtl
  CHECK(vertex_lines(read_text(dir / "a1" / frame_name("first", 1))).size() == 30);
  const std::string b_first = read_text(dir / "b1" / frame_name("second", 1));
  const auto b_v = vertex_lines(b_first);
  REQUIRE(b_v.size() == 4);
  CHECK(b_v[0] == "v 3 0 0");  // its own transform, numbered from its own 1
  CHECK(b_first.find("f 1/1/1 2/2/2 4/4/4") != std::string::npos);
  // The pins map of cloth a (grey above 0.5 for u > 0.5) pins its right half, columns 3..5 of 6.
  const auto a1 = vertex_lines(read_text(dir / "a1" / frame_name("first", 1)));
  const auto a6 = vertex_lines(read_text(dir / "a1" / frame_name("first", 6)));
  for (int v = 0; v < 30; ++v) CHECK((a1[v] == a6[v]) == (v % 6 >= 3));
  for (const char* c : {"a", "b"})
    for (const std::string& f : files_in(dir / (std::string(c) + "1"))) {
      INFO(f);
      CHECK(read_text(dir / (std::string(c) + "1") / f) == read_text(dir / (std::string(c) + "2") / f));
    }
}

TEST_CASE("a cloth's colour texture is passed through: frames reference an .mtl whose map_Kd finds the image") {
  const auto dir = scratch_dir("maps_mtl");
  std::filesystem::create_directories(dir / "art");
  write_png(dir / "art" / "colour.png", 2, 2, 3, 8, {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255});
  write_text(dir / "scene.xml", std::string("<scene>") + simulation + R"(
    <cloth name="c" grid="3 3" saveDir="out/frames" texture="art/colour.png"/>
    <cloth name="plain" grid="3 3" saveDir="out/frames"/></scene>)");
  const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet");
  REQUIRE_MESSAGE(r.exit_code == 0, r.output);
  const std::string frame = read_text(dir / "out" / "frames" / frame_name("c", 3));
  CHECK(frame.find("mtllib c.mtl\n") != std::string::npos);
  CHECK(frame.find("usemtl c\nf ") != std::string::npos);
  CHECK(read_text(dir / "out" / "frames" / frame_name("plain", 3)).find("mtllib") == std::string::npos);
  const std::string mtl = read_text(dir / "out" / "frames" / "c.mtl");
  CHECK(mtl.find("newmtl c\n") != std::string::npos);
  CHECK(mtl.find("map_Kd ../../art/colour.png\n") != std::string::npos);
  CHECK(std::filesystem::exists(dir / "out" / "frames" / "../../art/colour.png"));
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "frames" / "plain.mtl"));
}

TEST_CASE("bad maps: exit code 2, a message naming the file and the attribute, and no frame written") {
  const auto dir = scratch_dir("maps_bad");
  write_constant_png(dir / "ok.png", 4, 4, 128);
  write_text(dir / "empty.png", "");
  const std::string good = encode_png(16, 16, 1, 8, std::vector<std::uint16_t>(256, 7));
  write_text(dir / "truncated.png", good.substr(0, good.size() / 2));
  write_text(dir / "text.png", "this is not an image\n");
  write_text(dir / "huge.png", encode_png_header_only(20000, 20000));
  write_text(dir / "nouv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  struct Case {
    const char* cloth;      // attributes and children of <cloth>
    const char* expected;   // part of the message
  };
  const Case cases[] = {
      {R"(obj="nouv.obj"><stiffness min="1" max="2" map="ok.png"/>)", "<stiffness map="},
      {R"(grid="3 3"><stiffness min="1" max="2" map="missing.png"/>)", "missing.png: cannot read file"},
      {R"(grid="3 3"><damping min="1" max="2" map="empty.png"/>)", "empty.png: empty file"},
      {R"(grid="3 3"><density min="1" max="2" map="truncated.png"/>)", "truncated.png: PNG chunk IDAT at byte 33 declares"},
      {R"(grid="3 3"><thickness min="0.1" max="0.2" map="text.png"/>)", "text.png: cannot decode"},
      {R"(grid="3 3"><pins map="text.png"/>)", "<pins map="},
      // refused from its header, before stb allocates 400 MB for the pixels
      {R"(grid="3 3"><stiffness min="1" max="2" map="huge.png"/>)",
       "huge.png: image of 20000 x 20000 pixels; expected at most 268435456 pixels"},
      {R"(grid="3 3"><stiffness min="5" max="2" map="ok.png"/>)", "min=\"5\" is above max=\"2\""},
      {R"(grid="3 3"><damping min="-1" max="2" map="ok.png"/>)", "min=\"-1\""},
      {R"(grid="3 3"><density min="0" max="2" map="ok.png"/>)", "expected a positive number"},
      {R"(grid="3 3"><mass min="0.1" max="-2" map="ok.png"/>)", "max=\"-2\""},
      {R"(grid="3 3"><mass value="-0.5"/>)", "value=\"-0.5\""},
      {R"(grid="3 3"><stiffness value="3" min="1" max="2" map="ok.png"/>)", "not both"},
      {R"(grid="3 3"><stiffness min="1" map="ok.png"/>)", "needs all of"},
      {R"(grid="3 3"><density value="1"/><mass value="0.1"/>)", "<density> or <mass>"},
      {R"(grid="3 3"><mass value="0.1"/><density value="1"/>)", "<density> or <mass>"},
  };
  for (const Case& c : cases) {
    INFO(c.cloth);
    std::filesystem::remove_all(dir / "out");
    write_text(dir / "scene.xml", std::string("<scene>") + simulation + "\n<cloth name=\"x\" saveDir=\"out\" " +
                                      c.cloth + "</cloth></scene>");
    const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("scene.xml:2:") != std::string::npos);  // the file and the element's line
    CHECK(r.output.find(c.expected) != std::string::npos);
    CHECK(files_in(dir / "out").empty());
  }
}
