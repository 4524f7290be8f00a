// Attachments (core/attachments.h, systems/attachments.h): a skirt whose top ring is attached to a cylinder that
// translates and rotates as an OBJ sequence. A rigid motion keeps barycentric weights and the offset along the
// unit normal, so each attached vertex must sit at R_f x0 + T_f at every frame f, the hand computation.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cstring>

#include "core/attachments.h"
#include "core/error.h"
#include "systems/step.h"
#include "tests/support/collision_scene.h"
#include "tests/support/png_fixtures.h"

using namespace clothsim;
using clothsim::test::load_collision_scene;
using clothsim::test::scratch_dir;
using clothsim::test::write_text;

namespace {

constexpr int segments = 12, rings = 4, frames = 5;
constexpr Real body_radius = 0.1, skirt_radius = 0.105, top_y = 0.01;

std::string number(Real v) {
  char s[40];
  std::snprintf(s, sizeof s, "%.17g", v);
  return s;
}

// Rigid motion of the body at frame f (1-based): rotation about a tilted axis, then a translation.
Mat3 rotation(int f) {
  return Eigen::AngleAxis<Real>(0.15 * (f - 1), Vec3(0, 1, 0.3).normalized()).toRotationMatrix();
}
Vec3 translation(int f) { return Vec3(0.03, 0.02, -0.01) * Real(f - 1); }

// The body: an open cylinder of radius body_radius from y = -0.05 to 0.05, outward counter-clockwise triangles,
// moved by frame f's rigid motion.
std::string body_obj(int f) {
  std::string s;
  for (int r = 0; r < 2; ++r)
    for (int j = 0; j < segments; ++j) {
      const Real a = 2 * M_PI * j / segments;
      const Vec3 p = rotation(f) * Vec3(body_radius * std::cos(a), r ? 0.05 : -0.05, body_radius * std::sin(a)) +
                     translation(f);
      s += "v " + number(p.x()) + " " + number(p.y()) + " " + number(p.z()) + "\n";
    }
  for (int j = 0; j < segments; ++j) {
    const int b0 = 1 + j, b1 = 1 + (j + 1) % segments, t0 = b0 + segments, t1 = b1 + segments;
    s += "f " + std::to_string(b0) + " " + std::to_string(t0) + " " + std::to_string(b1) + "\n";
    s += "f " + std::to_string(b1) + " " + std::to_string(t0) + " " + std::to_string(t1) + "\n";
  }
  return s;
}

// The skirt: `rings` rings of `segments` vertices at radius skirt_radius, the top one (vertices 0..11) at
// y = top_y, each vertex half a segment from the body's vertical edges, so that it projects inside one body
// triangle. UVs: u 0.25 on the top ring, 0.75 below (a two-pixel map selects the top ring).
std::string skirt_obj() {
  std::string s;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const Real a = 2 * M_PI * (j + 0.5) / segments;
      s += "v " + number(skirt_radius * std::cos(a)) + " " + number(top_y - 0.04 * i) + " " +
           number(skirt_radius * std::sin(a)) + "\n";
      s += std::string("vt ") + (i == 0 ? "0.25" : "0.75") + " 0.5\n";
    }
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = 1 + i * segments + j, b = 1 + i * segments + (j + 1) % segments;
      const int c = a + segments, d = b + segments;
      auto corner = [](int v) { return std::to_string(v) + "/" + std::to_string(v); };
      s += "f " + corner(a) + " " + corner(c) + " " + corner(b) + "\n";
      s += "f " + corner(b) + " " + corner(c) + " " + corner(d) + "\n";
    }
  return s;
}

// The scene in `dir`: the skirt attached by `attach` (an <attach> element) to the body sequence, frames 1..5.
std::filesystem::path write_skirt_scene(const std::filesystem::path& dir, const std::string& integrator,
                                        const std::string& attach, const std::string& extra_colliders = "") {
  for (int f = 1; f <= frames; ++f) write_text(dir / ("body." + std::to_string(f) + ".obj"), body_obj(f));
  write_text(dir / "skirt.obj", skirt_obj());
  write_text(dir / "scene.xml", R"(<scene>
  <simulation timestep="0.001" fps="25" startFrame="1" endFrame=")" + std::to_string(frames) +
                                    R"(" integrator=")" + integrator + R"("/>
  <static name="body" sequence="body.#.obj"/>
)" + extra_colliders + R"(  <cloth name="skirt" obj="skirt.obj" saveDir="out">
    <density value="1"/><stiffness value="50"/><damping value="0.02"/><thickness value="0.002"/>
    )" + attach + R"(
  </cloth>
</scene>
)");
  return dir / "scene.xml";
}

std::string top_ring() {
  std::string s;
  for (int j = 0; j < segments; ++j) s += std::to_string(j) + " ";
  return "<attach collider=\"body\" vertices=\"" + s + "\"/>";
}

// Steps the scene through every frame; at each frame's end the attached vertices must be at the body's rigid
// motion of their start, and after every step their velocity must carry them over the step.
void check_follows(const std::string& integrator) {
  const auto dir = scratch_dir("attach_follow_" + integrator);
  auto sc = load_collision_scene(write_skirt_scene(dir, integrator, top_ring()));
  const Model& m = sc.built.model;
  REQUIRE(m.attach_particle.size() == std::size_t(segments));
  REQUIRE(m.pinned.size() == std::size_t(segments));
  State state = sc.built.state, next = state;
  const std::vector<Vec3> x0 = state.x;
  const SimOptions& o = sc.built.options;
  Workspace ws = make_workspace(m, o);
  const sim::ColliderTrack track(sc.desc);
  Real worst = 0, worst_velocity = 0;
  for (int f = 2; f <= frames; ++f) {
    track.prepare(m, f, ws.collision);
    for (int k = 0; k < o.steps_per_frame; ++k) {
      step(m, o, state, next, ws, o.dt);
      for (Index i : m.attach_particle) {
        const Vec3 moved = next.x[i] - state.x[i];
        worst_velocity = std::max(worst_velocity, (next.v[i] * o.dt - moved).norm() / moved.norm());
      }
      std::swap(state, next);
    }
    for (Index i : m.attach_particle) {
      const Vec3 expected = rotation(f) * x0[i] + translation(f);
      worst = std::max(worst, (state.x[i] - expected).norm() / expected.norm());
    }
  }
  CHECK(worst <= 1e-12);
  CHECK(worst_velocity <= 1e-9);
  // The free rings were dragged along: the lowest ring's centre moved with the body, most of its 9 cm.
  Vec3 centre = Vec3::Zero();
  for (Index i = (rings - 1) * segments; i < rings * segments; ++i) centre += state.x[i] / segments;
  CHECK(centre.x() > 0.045);
}

}  // namespace

TEST_CASE("attachments: binding at the first frame is the projection on the nearest body triangle") {
  const auto dir = scratch_dir("attach_bind");
  const auto sc = load_collision_scene(write_skirt_scene(dir, "symplectic", top_ring()));
  const Model& m = sc.built.model;
  REQUIRE(m.attach_particle.size() == std::size_t(segments));
  for (std::size_t k = 0; k < m.attach_particle.size(); ++k) {
    CHECK(m.attach_particle[k] == Index(k));
    CHECK(m.particle_inv_mass[k] == 0);
    // Half a segment from the edges, the vertex faces the middle of a flat facet at R cos(pi / segments).
    CHECK(m.attach_offset[k] == doctest::Approx(skirt_radius - body_radius * std::cos(M_PI / segments)).epsilon(1e-12));
    const Vec3& w = m.attach_weight[k];
    CHECK(w.minCoeff() > 0);
    CHECK(w.sum() == doctest::Approx(1).epsilon(1e-14));
    // The bound point is the vertex itself.
    const Index* v = &m.collision.mesh_tri_index[3 * m.attach_tri[k]];
    const auto& y = m.collision.mesh_x;
    CHECK((attachment_point(w, m.attach_offset[k], y[v[0]], y[v[1]], y[v[2]]) - sc.built.state.x[k]).norm() <= 1e-15);
  }
}

TEST_CASE("attachments: a skirt's top ring follows a translating, rotating body exactly (symplectic)") {
  check_follows("symplectic");
}

TEST_CASE("attachments: a skirt's top ring follows a translating, rotating body exactly (implicit)") {
  check_follows("implicit");
}

TEST_CASE("attachments: the same bytes at 1 and 2 threads") {
  const auto dir = scratch_dir("attach_threads");
  const auto sc = load_collision_scene(write_skirt_scene(dir, "symplectic", top_ring()));
  std::vector<State> end;
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    sim::Simulation simulation(sc);
    while (simulation.next_frame() <= frames) REQUIRE_FALSE(simulation.advance_frame().diverged);
    end.push_back(simulation.state());
  }
  CHECK(std::memcmp(end[0].x.data(), end[1].x.data(), end[0].x.size() * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(end[0].v.data(), end[1].v.data(), end[0].v.size() * sizeof(Vec3)) == 0);
}

TEST_CASE("attachments: map=\"image\" attaches the vertices above half grey") {
  const auto dir = scratch_dir("attach_map");
  test::write_png(dir / "waist.png", 2, 1, 1, 8, {255, 0});  // u 0.25 white (the top ring), u 0.75 black
  const auto path = write_skirt_scene(dir, "symplectic", "<attach collider=\"body\" map=\"waist.png\"/>");
  const BuiltScene built = load_collision_scene(path).built;
  std::vector<Index> expected(segments);
  for (int j = 0; j < segments; ++j) expected[j] = j;
  CHECK(built.model.attach_particle == expected);
}

TEST_CASE("attachments: bad <attach> inputs name the scene file and line") {
  const auto dir = scratch_dir("attach_bad");
  auto message = [&](const std::string& attach, const std::string& colliders = "") {
    try {
      load_collision_scene(write_skirt_scene(dir, "symplectic", attach, colliders));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string file = (dir / "scene.xml").string() + ":6: ";
  CHECK(message("<attach collider=\"bodi\" vertices=\"0\"/>") ==
        file + "cloth 'skirt' <attach collider=\"bodi\">: no collider has that name; expected one of: 'body'");
  CHECK(message("<attach collider=\"body\" vertices=\"0 48\"/>") ==
        file + "cloth 'skirt' <attach collider=\"body\">: vertex 48 is out of range (the mesh has 48 vertices, "
               "numbered from 0)");
  const std::string ball = "  <sphere name=\"ball\" center=\"0 1 0\" radius=\"0.1\"/>\n";
  CHECK(message("<attach collider=\"ball\" vertices=\"0\"/>", ball).find(
            ":7: cloth 'skirt' <attach collider=\"ball\">: the collider is a sphere; expected a mesh collider") !=
        std::string::npos);
  const std::string ground = "  <plane name=\"ground\"/>\n";
  CHECK(message("<attach collider=\"ground\" vertices=\"0\"/>", ground).find("the collider is a plane") !=
        std::string::npos);
  CHECK(message("<attach collider=\"body\"/>").find(
            ":6: <attach>: expected exactly one of vertices=\"i j ...\" or map=\"image\"") != std::string::npos);
  CHECK(message("<attach vertices=\"0\"/>").find(":6: <attach>: attribute collider=\"\"") != std::string::npos);
  CHECK(message("<attach collider=\"body\" vertices=\"0 -1\"/>").find("expected vertex indices") != std::string::npos);

  // Through the command line: exit code 2.
  write_skirt_scene(dir, "symplectic", "<attach collider=\"bodi\" vertices=\"0\"/>");
  const auto r = test::run_cli("run --quiet " + (dir / "scene.xml").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("scene.xml:6: cloth 'skirt' <attach collider=\"bodi\">: no collider has that name") !=
        std::string::npos);
}

TEST_CASE("attachments: validate counts the attached vertices among the pinned") {
  const auto dir = scratch_dir("attach_validate");
  const auto path = write_skirt_scene(dir, "symplectic", top_ring());
  const test::CliResult r = test::run_cli("validate " + path.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  // The top ring: 12 vertices attached, and an attached vertex is a pin whose position the body prescribes.
  CHECK(r.output.find("pinned 12 (attached 12)") != std::string::npos);
}
