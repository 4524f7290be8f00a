// <cloth rest="...">: rest lengths and masses from another mesh with the same vertices and triangles
// (io/rest_shape.h, core/build_model.cpp). A sheet whose rest mesh is itself scaled by 1.1 has every rest length
// 1.1 times its own, 1.21 times its mass, and, free in space, grows to 1.1 times its width.
#include <doctest/doctest.h>

#include "core/error.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;
using clothsim::test::load_collision_scene;
using clothsim::test::scratch_dir;
using clothsim::test::write_text;

namespace {

constexpr int n = 4;            // vertices per side
constexpr Real spacing = 0.1;   // m

// An n x n sheet in the xz-plane scaled by s, two triangles a cell; `flip` reverses the first triangle.
std::string sheet_obj(Real s, int vertices = n * n, bool flip = false) {
  std::string t;
  char line[128];
  for (int k = 0; k < vertices; ++k) {
    std::snprintf(line, sizeof line, "v %.17g 0 %.17g\n", s * spacing * (k % n), s * spacing * (k / n));
    t += line;
  }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = 1 + j * n + i, b = a + 1, c = a + n, d = c + 1;
      const bool first = flip && i == 0 && j == 0;
      std::snprintf(line, sizeof line, first ? "f %d %d %d\nf %d %d %d\n" : "f %d %d %d\nf %d %d %d\n", a,
                    first ? d : c, first ? c : d, a, d, b);
      t += line;
    }
  return t;
}

std::filesystem::path write_scene(const std::filesystem::path& dir, const std::string& rest_obj) {
  write_text(dir / "sheet.obj", sheet_obj(1));
  write_text(dir / "pattern.obj", rest_obj);
  write_text(dir / "scene.xml", R"(<scene>
  <simulation timestep="0.01" fps="25" startFrame="1" endFrame="26" integrator="implicit" gravity="0 0 0"/>
  <forces><airDamping value="2"/></forces>
  <cloth name="sheet" obj="sheet.obj" rest="pattern.obj" saveDir="out">
    <stiffness value="100"/><density value="0.2"/>
  </cloth>
</scene>
)");
  return dir / "scene.xml";
}

std::string load_error(const std::filesystem::path& scene) {
  try {
    load_collision_scene(scene);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("rest shape: rest lengths and masses from a rest mesh scaled by 1.1") {
  const auto dir = scratch_dir("rest_scaled");
  const auto sc = load_collision_scene(write_scene(dir, sheet_obj(1.1)));
  const Model& m = sc.built.model;
  const std::vector<Vec3>& x = sc.built.state.x;
  REQUIRE(m.spring_count > 0);
  int edges = 0;
  for (Index s = 0; s < m.spring_count; ++s) {
    CHECK(m.spring_rest[s] == doctest::Approx(1.1 * (x[m.spring_b[s]] - x[m.spring_a[s]]).norm()).epsilon(1e-14));
    // Hand values of the edge springs (listed first): a side 0.11 m, a diagonal 0.11 sqrt(2) m.
    const Real r = m.spring_rest[s];
    if (s < m.spring_kind_total[int(SpringKind::edge)])
      edges += std::abs(r - 0.11) < 1e-14 || std::abs(r - 0.11 * std::sqrt(2.0)) < 1e-14;
  }
  // 2 n (n - 1) sides and (n - 1)^2 diagonals.
  CHECK(m.spring_kind_total[int(SpringKind::edge)] == 2 * n * (n - 1) + (n - 1) * (n - 1));
  CHECK(edges == 2 * n * (n - 1) + (n - 1) * (n - 1));
  Real mass = 0;
  for (Real w : m.particle_inv_mass) mass += 1 / w;
  CHECK(mass == doctest::Approx(0.2 * std::pow(1.1 * spacing * (n - 1), 2)).epsilon(1e-12));
}

TEST_CASE("rest shape: a free sheet grows to its rest mesh's size") {
  const auto dir = scratch_dir("rest_grow");
  auto sc = load_collision_scene(write_scene(dir, sheet_obj(1.1)));
  const Real width0 = (sc.built.state.x[n - 1] - sc.built.state.x[0]).norm();
  Real width = 0;
  test::run_frames(sc, [&](int, const Model&, const State& s, const Workspace&) { width = (s.x[n - 1] - s.x[0]).norm(); });
  CHECK(width0 == doctest::Approx(0.3).epsilon(1e-15));
  CHECK(width / width0 == doctest::Approx(1.1).epsilon(0.002));
}

TEST_CASE("rest shape: a rest mesh of other vertices or triangles names both files") {
  const auto dir = scratch_dir("rest_mismatch");
  const std::string scene = (dir / "scene.xml").string(), sheet = (dir / "sheet.obj").string(),
                    pattern = (dir / "pattern.obj").string();
  CHECK(load_error(write_scene(dir, sheet_obj(1.1, n * n + 1))) ==
        scene + ":4: cloth 'sheet': rest mesh '" + pattern + "' has 17 vertices and 18 triangles; expected the 16 "
                "vertices and 18 triangles of '" + sheet + "'");
  CHECK(load_error(write_scene(dir, sheet_obj(1.1, n * n, true))) ==
        scene + ":4: cloth 'sheet': rest mesh '" + pattern + "' differs in triangle 0 (vertices 0 5 4, counted from "
                "0); expected the triangles of '" + sheet + "' in the same order (0 4 5)");
  const auto r = test::run_cli("run --quiet " + scene);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("scene.xml:4: cloth 'sheet': rest mesh") != std::string::npos);
}
