// core/limits.h: inputs past the documented sizes are refused with a clear error before anything is allocated.
#include <doctest/doctest.h>

#include <string>

#include "core/error.h"
#include "core/limits.h"
#include "io/obj_reader.h"
#include "io/scene_xml.h"
#include "tests/support/cli_harness.h"

using namespace clothsim;
namespace fs = std::filesystem;

TEST_CASE("a file over the input size limit is refused before it is read") {
  const fs::path dir = test::scratch_dir("limits_file");
  const fs::path big = dir / "huge.obj";
  test::write_text(big, "v 0 0 0\n");
  fs::resize_file(big, limits::max_input_file_bytes + 1);  // sparse: no disk space used
  CHECK_THROWS_WITH_AS(io::read_obj(big.string()),
                       doctest::Contains("file of 2147483649 bytes; expected at most 2147483648"), Error);
}

TEST_CASE("a grid over the vertex limit is refused and one at the limit is read") {
  const fs::path dir = test::scratch_dir("limits_grid");
  auto scene = [&](const std::string& grid) {
    test::write_text(dir / "s.xml", "<scene>\n<cloth grid=\"" + grid + "\"/>\n</scene>\n");
    return (dir / "s.xml").string();
  };
  // 4096 * 4096 = 2^24 vertices: the limit itself
  CHECK(io::read_scene(scene("4096 4096")).cloths[0].grid_nx == 4096);
  CHECK_THROWS_WITH_AS(io::read_scene(scene("4097 4096")),
                       doctest::Contains("s.xml:2: <cloth>: attribute grid=\"4097 4096\"; expected two integers "
                                         "\"NX NY\", each >= 2, with NX * NY <= 16777216"),
                       Error);
}

TEST_CASE("an OBJ face of 256 corners is refused (tinyobjloader counts corners in a byte)") {
  const fs::path dir = test::scratch_dir("limits_face");
  std::string obj, face = "f";
  for (int i = 0; i < 256; ++i) {
    // corners on a circle, so the fan's triangles have area
    obj.append("v ").append(std::to_string(std::cos(i * 0.0245))).append(" ");
    obj.append(std::to_string(std::sin(i * 0.0245))).append(" 0\n");
    face.append(" ").append(std::to_string(i + 1));
  }
  test::write_text(dir / "fan.obj", obj + face + "\n");
  CHECK_THROWS_WITH_AS(io::read_obj((dir / "fan.obj").string()),
                       doctest::Contains("fan.obj:257: face with 256 corners; expected at most 255"), Error);
  // 255 corners: read as a fan of 253 triangles
  face.resize(face.rfind(' '));
  test::write_text(dir / "fan.obj", obj + face + "\n");
  CHECK(io::read_obj((dir / "fan.obj").string()).triangle_count() == 253);
}
