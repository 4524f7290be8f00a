// Several cloths in one scene: which pairs the model tests (core/build_collision.cpp: a cloth with itself only
// under selfCollision, two cloths under clothCollision), and a sheet dropped onto another, checked against the
// independent checks of systems/collision/collision_check.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <random>

#include "systems/collision/collide.h"
#include "systems/collision/collision_check.h"
#include "systems/collision/proximity.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;
using clothsim::test::load_collision_scene;
using clothsim::test::run_frames;
using clothsim::test::scratch_dir;
using clothsim::test::write_text;

namespace {

test::LoadedCollisionScene load_xml(const std::string& name, const std::string& xml) {
  const auto dir = scratch_dir("cloth_collision_" + name);
  write_text(dir / "s.xml", xml);
  return load_collision_scene(dir / "s.xml");
}

// Vertex indices on the border of an n x n grid (index j * n + i).
std::string border_pins(int n) {
  std::string s;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (i == 0 || j == 0 || i == n - 1 || j == n - 1) s += std::to_string(j * n + i) + " ";
  return s;
}

// A 1 m trampoline (16 x 16, border pinned) at y = 0.5 and a 0.5 m sheet (10 x 10) dropped on it from 0.1 m
// above; both 1 cm thick, neither self-colliding. A ground plane at y = 0 catches the sheet when it falls through.
constexpr Real drop_thickness = 0.01;
std::string drop_scene(const char* cloth_collision, int end_frame, const char* broad = "hash",
                       const char* integrator = "symplectic", Real timestep = 0.0005) {
  char xml[4096];
  std::snprintf(xml, sizeof xml, R"(<scene>
  <simulation timestep="%g" integrator="%s" fps="24" startFrame="1" endFrame="%d" collisionIterations="2"
              clothCollision="%s" broadPhase="%s"/>
  <forces><airDamping value="1"/></forces>
  <plane name="ground" point="0 0 0" normal="0 1 0"/>
  <cloth name="lower" grid="16 16" size="1 1" translate="0 0.5 0">
    <density value="0.2"/><stiffness value="200"/><thickness value="%g"/><pins vertices="%s"/>
  </cloth>
  <cloth name="upper" grid="10 10" size="0.5 0.5" translate="0.013 0.6 -0.021">
    <density value="0.2"/><stiffness value="200"/><thickness value="%g"/>
  </cloth></scene>)",
                timestep, integrator, end_frame, cloth_collision, broad, drop_thickness, border_pins(16).c_str(),
                drop_thickness);
  return xml;
}

struct DropResult {
  Index below = 0;            // upper vertices under the lower sheet, summed over frames
  Index intersecting = 0;     // intersecting triangle pairs, summed over frames
  Real contact_gap = 0;       // last frame: 10th-percentile distance of the upper's vertices to the lower sheet, m
  Real kinetic = 0;           // last frame: kinetic energy of both sheets, J
  std::vector<Vec3> last;     // last frame's positions
};

DropResult run_drop(const std::string& xml) {
  auto sc = load_xml("drop", xml);
  const Model& m = sc.built.model;
  const ClothInfo& lower = m.cloths[0];
  const ClothInfo& upper = m.cloths[1];
  DropResult r;
  std::vector<Vec3> previous;
  run_frames(sc, [&](int, const Model&, const State& s, const Workspace&) {
    // The lower sheet is a height field (pinned at its border, sagging): a vertex is under it when a vertical
    // segment up from the vertex crosses one of its triangles.
    Index below = 0;
    for (Index i = upper.particle_begin; i < upper.particle_end; ++i)
      for (Index t = lower.tri_begin; t < lower.tri_end; ++t) {
        const Index* v = &m.tri_index[3 * t];
        below += segment_crosses_triangle(s.x[i], s.x[i] + Vec3(0, 10, 0), s.x[v[0]], s.x[v[1]], s.x[v[2]]);
      }
    r.below += below;
    r.intersecting += count_intersecting_triangles(m, s.x);
    previous = s.x;
    r.kinetic = 0;
    for (Index i = 0; i < m.particle_count; ++i)
      if (m.particle_inv_mass[i] > 0) r.kinetic += 0.5 * s.v[i].squaredNorm() / m.particle_inv_mass[i];
  });
  r.last = previous;
  std::vector<Real> gaps;
  for (Index i = upper.particle_begin; i < upper.particle_end; ++i) {
    Real best = 1e300;
    for (Index t = lower.tri_begin; t < lower.tri_end; ++t) {
      const Index* v = &m.tri_index[3 * t];
      best = std::min(best, point_triangle_distance(r.last[i], r.last[v[0]], r.last[v[1]], r.last[v[2]]));
    }
    gaps.push_back(best);
  }
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 10, gaps.end());
  r.contact_gap = gaps[gaps.size() / 10];
  return r;
}

}  // namespace

TEST_CASE("cloth pairs: a cloth meets itself only under selfCollision, two cloths under clothCollision") {
  // a self-colliding, b and c plain, d opted out of cloth-cloth contact.
  auto sc = load_xml("pairs", R"(<scene>
    <cloth name="a" grid="3 3" selfCollision="true"/>
    <cloth name="b" grid="4 4" translate="2 0 0"/>
    <cloth name="c" grid="3 3" translate="4 0 0"/>
    <cloth name="d" grid="3 3" translate="6 0 0" clothCollision="false"/></scene>)");
  const CollisionModel& c = sc.built.model.collision;
  REQUIRE(c.enabled);
  REQUIRE(c.cloth_count == 4);
  const std::uint8_t expected[16] = {1, 1, 1, 0,   // a: itself, b, c
                                     1, 0, 1, 0,   // b: a, c
                                     1, 1, 0, 0,   // c: a, b
                                     0, 0, 0, 0};  // d: nothing
  CHECK(std::equal(c.cloth_pair.begin(), c.cloth_pair.end(), expected));
  // Only triangles that can meet something enter the broad phase: a, b, c (8 + 18 + 8), not d.
  CHECK(c.prim.size() == 8 + 18 + 8);
  for (Index p : c.prim) CHECK(p < sc.built.model.cloths[3].tri_begin);
  // Edges of a 3 x 3 grid: 12 structural + 4 diagonals; of a 4 x 4: 24 + 9.
  CHECK(c.edge_a.size() == 16 + 33 + 16);
}

TEST_CASE("cloth pairs: model no more than the scene needs") {
  SUBCASE("one cloth, no selfCollision, no collider: nothing") {
    auto sc = load_xml("one", R"(<scene><cloth name="a" grid="4 4"/></scene>)");
    CHECK_FALSE(sc.built.model.collision.enabled);
    CHECK(sc.built.model.collision.cloth_pair.empty());
  }
  SUBCASE("two cloths with clothCollision off: nothing") {
    auto sc = load_xml("off", R"(<scene><simulation clothCollision="false"/>
      <cloth name="a" grid="4 4"/><cloth name="b" grid="4 4" translate="0 1 0"/></scene>)");
    CHECK_FALSE(sc.built.model.collision.enabled);
    CHECK(sc.built.model.collision.prim.empty());
  }
  SUBCASE("two cloths, one opted out: nothing for cloth pairs") {
    auto sc = load_xml("opt_out", R"(<scene>
      <cloth name="a" grid="4 4"/><cloth name="b" grid="4 4" translate="0 1 0" clothCollision="false"/></scene>)");
    CHECK_FALSE(sc.built.model.collision.enabled);
  }
  SUBCASE("clothCollision off, one self-colliding cloth: only its own triangles and edges") {
    auto sc = load_xml("self_only", R"(<scene><simulation clothCollision="false"/>
      <cloth name="a" grid="4 4"/><cloth name="b" grid="3 3" translate="0 1 0" selfCollision="true"/></scene>)");
    const CollisionModel& c = sc.built.model.collision;
    CHECK(c.enabled);
    CHECK(c.prim.size() == 8);
    CHECK(c.edge_a.size() == 16);
    CHECK(c.cloth_pair == std::vector<std::uint8_t>{0, 0, 0, 1});
  }
  SUBCASE("two cloths by default: their triangles, no self pairs") {
    auto sc = load_xml("default", R"(<scene>
      <cloth name="a" grid="4 4"/><cloth name="b" grid="3 3" translate="0 1 0"/></scene>)");
    const CollisionModel& c = sc.built.model.collision;
    CHECK(c.enabled);
    CHECK(c.prim.size() == 18 + 8);
    CHECK(c.cloth_pair == std::vector<std::uint8_t>{0, 1, 1, 0});
  }
}

namespace {

// The body of a scene of two 12 x 12 sheets of 0.5 m, 2 cm thick, in the same place, after <scene> and any
// <simulation>.
const char* two_sheets_xml = R"(
      <cloth name="a" grid="12 12" size="0.5 0.5"><thickness value="0.02"/></cloth>
      <cloth name="b" grid="12 12" size="0.5 0.5"><thickness value="0.02"/></cloth></scene>)";

// The sheets crumpled: heights scattered over 8 cm at the step's start, each vertex moved by up to 5 mm an axis.
void crumple_sheets(std::uint32_t seed, State& in, State& out) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> height(-0.04, 0.04), small(-0.005, 0.005);
  out = in;
  for (std::size_t i = 0; i < in.x.size(); ++i) {
    in.x[i].y() += height(rng);
    out.x[i] = in.x[i] + Vec3(small(rng), small(rng), small(rng));
  }
}

}  // namespace

TEST_CASE("cloth pairs: two crumpled sheets report only pairs of different cloths, the same by hash, BVH, brute") {
  std::string xml[2];
  for (int k = 0; k < 2; ++k)
    xml[k] = std::string(R"(<scene><simulation broadPhase=")") + (k ? "bvh" : "hash") + "\"/>" + two_sheets_xml;
  auto hash = load_xml("crumpled_hash", xml[0]);
  auto bvh = load_xml("crumpled_bvh", xml[1]);
  const Model& m = hash.built.model;
  // Both sheets in the same place, heights scattered over 8 cm: each sheet is within the thickness of itself
  // as much as of the other, so a pair of one cloth would show up if the filter let it through.
  State in = hash.built.state, out;
  crumple_sheets(11, in, out);
  Workspace wh = make_workspace(m, hash.built.options);
  Workspace wb = make_workspace(bvh.built.model, bvh.built.options);
  build_broad_phase(m, in, out, wh.collision);
  build_broad_phase(bvh.built.model, in, out, wb.collision);
  const auto by_brute = list_proximities(m, in, out, wh.collision, BroadMode::brute);
  CHECK(list_proximities(m, in, out, wh.collision, BroadMode::hash) == by_brute);
  CHECK(list_proximities(bvh.built.model, in, out, wb.collision, BroadMode::bvh) == by_brute);
  const auto& cloth = m.collision.particle_cloth;
  Index vertex_pairs = 0, edge_pairs = 0;
  for (const auto& [kind, a, b] : by_brute) {
    if (kind == 0) {
      ++vertex_pairs;
      CHECK(cloth[a] != cloth[m.tri_index[3 * b]]);
    } else {
      ++edge_pairs;
      CHECK(cloth[m.collision.edge_a[a]] != cloth[m.collision.edge_a[b]]);
    }
  }
  CHECK(vertex_pairs > 50);
  CHECK(edge_pairs > 50);
}

TEST_CASE("a scene that names no broad phase gets the BVH: no hash is built, the brute-force pairs are found") {
  auto sc = load_xml("default_broad", std::string("<scene>") + two_sheets_xml);
  const Model& m = sc.built.model;
  REQUIRE(m.collision.broad_phase == BroadPhase::bvh);
  CHECK(broad_mode(m.collision) == BroadMode::bvh);
  State in = sc.built.state, out;
  crumple_sheets(13, in, out);
  Workspace ws = make_workspace(m, sc.built.options);
  build_broad_phase(m, in, out, ws.collision);
  CHECK(ws.collision.hash.table_size == 0);
  const auto by_brute = list_proximities(m, in, out, ws.collision, BroadMode::brute);
  CHECK(by_brute.size() > 100);
  CHECK(list_proximities(m, in, out, ws.collision, broad_mode(m.collision)) == by_brute);
}

namespace {

// The upper sheet never went under the lower, no triangles intersected, and it rests on it at the end.
void check_rests_on_lower(const DropResult& r) {
  CHECK(r.below == 0);
  CHECK(r.intersecting == 0);
  // The collide stage keeps a vertex one thickness from a triangle (Bridson et al. 2002 §6.1): the vertices in
  // contact (the lowest tenth) rest that far above the lower sheet. The rest of the sheet does not lie flat: the
  // cloth-cloth repulsion (systems/collision/response.h) kicks vertices up, see docs/scene-format.md.
  CHECK(r.contact_gap > 0.7 * drop_thickness);
  CHECK(r.contact_gap < 1.3 * drop_thickness);
  // It did land: its lowest vertex rests on the trampoline, which it pushed below its pinned border (0.5 m).
  Real lowest = 1;
  for (Index i = 256; i < 356; ++i) lowest = std::min(lowest, r.last[i].y());
  CHECK(lowest < 0.5);
  CHECK(lowest > 0.4);
}

}  // namespace

TEST_CASE("two sheets, neither self-colliding: the upper lands on the lower and stays a thickness above it") {
  check_rests_on_lower(run_drop(drop_scene("true", 24)));

  // The same scene with clothCollision="false": the sheet falls through (so the checks above can fail).
  const DropResult off = run_drop(drop_scene("false", 24));
  CHECK(off.below >= 100);  // every one of its 100 vertices ends under the lower sheet
  for (Index i = 256; i < 356; ++i) CHECK(off.last[i].y() < 0.1);
}

TEST_CASE("two sheets, implicit at 2 ms (4x the explicit limit): the upper settles on the lower, no crossing") {
  // Symplectic Euler diverges on this pair from 0.5 ms (the light corner vertices' spring damping, see
  // docs/scene-format.md); backward Euler at 2 ms settles. 2 s: the drop's 0.0245 J (0.05 kg falling 0.05 m
  // onto the sheet) must be gone to within a thousandth, and the sheet rest a thickness above the lower one.
  const DropResult r = run_drop(drop_scene("true", 48, "hash", "implicit", 0.002));
  check_rests_on_lower(r);
  CHECK(r.kinetic < 2.45e-5);
}

TEST_CASE("two sheets: the same bytes at 1 and 2 threads, with hash and with BVH") {
  for (const char* broad : {"hash", "bvh"}) {
    std::vector<Vec3> result[2];
    for (int t = 1; t <= 2; ++t) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, t);
      result[t - 1] = run_drop(drop_scene("true", 12, broad)).last;  // contact from frame 5 on
    }
    REQUIRE(result[0].size() == result[1].size());
    CHECK(std::memcmp(result[0].data(), result[1].data(), result[0].size() * sizeof(Vec3)) == 0);
  }
}

namespace {

// One collide stage on two strips of different cloths touching edge to edge only: strip B lies flat at y = 0
// over x in [0, 0.2], z in [-0.1, 0.1]; strip A stands upright in the plane z = 0, its bottom edge from
// x = -0.1 to 0.3 at y = 3 mm (within the 5 mm thickness of B's edges at x = 0, 0.2 and its diagonal, while no
// vertex comes within the thickness of a triangle), moving down at 0.5 m/s and sliding along z at 2 m/s. Returns
// A's velocities after the stage.
std::vector<Vec3> sliding_strip(Real friction_a, Real friction_b) {
  char xml[1024];
  std::snprintf(xml, sizeof xml, R"(<scene>
  <simulation timestep="0.001" fps="100" startFrame="1" endFrame="2" collisionIterations="1"/>
  <cloth name="b" grid="2 2" size="0.2 0.2" translate="0.1 0 0" friction="%g"><thickness value="0.005"/></cloth>
  <cloth name="a" grid="2 2" size="0.4 0.2" rotate="90 0 0" translate="0.1 0.103 0" friction="%g">
    <thickness value="0.005"/></cloth>
</scene>)", friction_b, friction_a);
  auto sc = load_xml("friction_mean", xml);
  const Model& m = sc.built.model;
  const ClothInfo& a = m.cloths[1];
  const Real h = 0.001;
  State in = sc.built.state;
  for (Index i = a.particle_begin; i < a.particle_end; ++i) in.v[i] = Vec3(0, -0.5, 2);
  State out = in;
  for (Index i = 0; i < m.particle_count; ++i) out.x[i] = in.x[i] + h * in.v[i];
  Workspace ws = make_workspace(m, sc.built.options);
  REQUIRE(collide(m, in, out, ws, h).contacts > 0);
  return std::vector<Vec3>(out.v.begin() + a.particle_begin, out.v.begin() + a.particle_end);
}

}  // namespace

TEST_CASE("edge-edge contact between two cloths combines their frictions the same whichever cloth owns which edge") {
  // The geometric mean: 0.3 and 0.6 either way round give the same velocities to the bit, and a frictionless
  // cloth (0 against 1, either way round) makes the contact frictionless: the bytes of 0 against 0.
  const std::vector<Vec3> ab = sliding_strip(0.3, 0.6), ba = sliding_strip(0.6, 0.3);
  CHECK(std::memcmp(ab.data(), ba.data(), ab.size() * sizeof(Vec3)) == 0);
  const std::vector<Vec3> frictionless = sliding_strip(0, 0);
  const std::vector<Vec3> a_slippery = sliding_strip(0, 1), b_slippery = sliding_strip(1, 0);
  CHECK(std::memcmp(frictionless.data(), a_slippery.data(), frictionless.size() * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(frictionless.data(), b_slippery.data(), frictionless.size() * sizeof(Vec3)) == 0);
  // And the contact acted: A lost sliding speed against the frictionless pair, and its approach (0.5 m/s down)
  // slowed (the impulse is shared with B, which is free too, and averaged per vertex).
  const std::vector<Vec3> mean = sliding_strip(0.5, 0.5);
  Real slowed = 0, highest_vy = -1e9;
  for (std::size_t k = 0; k < mean.size(); ++k) {
    slowed = std::max(slowed, frictionless[k].z() - mean[k].z());
    highest_vy = std::max(highest_vy, mean[k].y());
  }
  CHECK(slowed > 0.01);
  CHECK(highest_vy > -0.4);
  MESSAGE("largest sliding speed lost to friction " << slowed << " m/s; highest vertical speed " << highest_vy);
}
