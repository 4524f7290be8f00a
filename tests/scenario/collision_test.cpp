// Scenario tests of the collide stage, each against a figure: a closed form (Coulomb incline, restitution), an
// independent check (vertices inside, crossing triangles), or another broad phase.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <random>

#include "systems/collision/collide.h"
#include "systems/collision/collision_check.h"
#include "systems/collision/proximity.h"
#include "systems/step.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;
using clothsim::test::load_collision_scene;
using clothsim::test::scratch_dir;
using clothsim::test::write_text;

namespace {

Vec3 centroid(const State& s) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : s.x) c += p;
  return c / Real(s.x.size());
}

Real centroid_v(const State& s) {
  Real v = 0;
  for (const Vec3& p : s.v) v += p.y();
  return v / Real(s.v.size());
}

}  // namespace

using clothsim::test::run_frames;

TEST_CASE("vertex-triangle proximity: Cramer barycentrics, tolerance delta = h / longest edge") {
  TriangleProximity p;
  // Unit right triangle in z = 0; a point above (0.25, 0.25) at height 0.01.
  REQUIRE(vertex_triangle_proximity(Vec3(0.25, 0.25, 0.01), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0.02, p));
  CHECK(p.d == doctest::Approx(0.01));
  CHECK(p.w[0] == doctest::Approx(0.5));
  CHECK(p.w[1] == doctest::Approx(0.25));
  CHECK(p.w[2] == doctest::Approx(0.25));
  // Just past the hypotenuse: w0 = -0.01 is within delta = 0.02 / sqrt(2) = 0.0141, -0.02 is not.
  CHECK(vertex_triangle_proximity(Vec3(0.505, 0.505, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0.02, p));
  CHECK_FALSE(vertex_triangle_proximity(Vec3(0.51, 0.51, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0.02, p));
}

TEST_CASE("edge-edge proximity: closest points of crossing and skew segments") {
  EdgeProximity e;
  REQUIRE(edge_edge_proximity(Vec3(-1, 0, 0.1), Vec3(1, 0, 0.1), Vec3(0, -1, 0), Vec3(0, 1, 0), e));
  CHECK(e.d == doctest::Approx(0.1));
  CHECK(e.s == doctest::Approx(0.5));
  CHECK(e.t == doctest::Approx(0.5));
  CHECK(e.n.z() == doctest::Approx(1));
  // End points closest: segments along x, the second shifted past the first's end.
  REQUIRE(edge_edge_proximity(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1, 0), Vec3(3, 1, 0), e));
  CHECK(e.d == doctest::Approx(std::sqrt(2.0)));
  CHECK(e.s == doctest::Approx(1));
  CHECK(e.t == doctest::Approx(0));
}

TEST_CASE("drape over a sphere: no cloth vertex inside the sphere at any frame") {
  const auto dir = scratch_dir("collision_drape");
  write_text(dir / "s.xml", R"(<scene>
  <simulation timestep="0.0005" fps="24" startFrame="1" endFrame="30"/>
  <sphere name="ball" center="0 0 0" radius="0.3" friction="0.4"/>
  <cloth name="c" grid="16 16" size="1 1" translate="0 0.35 0" friction="0.4">
    <density value="0.5"/><stiffness value="100" bend="0.1"/><thickness value="0.01"/>
  </cloth></scene>)");
  auto sc = load_collision_scene(dir / "s.xml");
  Real worst = 1e9;
  Index inside = 0;
  run_frames(sc, [&](int, const Model& m, const State& s, const Workspace& ws) {
    worst = std::min(worst, min_collider_distance(m, s.x, ws.collision, 0));
    inside += count_inside(m, s.x, ws.collision, 0);
  });
  CHECK(inside == 0);
  CHECK(worst > 0.009);  // the response keeps the thickness, 0.01 m
  // The sheet did drape: its corners fell well below the top of the sphere.
}

// A 4x4 cloth resting on a plane tilted by theta about z, for 2 s; the cloth's and the plane's friction (0.5 and
// 0.5 combine to 0.5).
Real incline_travel(Real tan_theta, Real mu_cloth = 0.5, Real mu_plane = 0.5) {
  const Real theta = std::atan(tan_theta), deg = theta * 180 / M_PI;
  const Vec3 n(-std::sin(theta), std::cos(theta), 0);
  const Real h = 0.005;
  const auto dir = scratch_dir("collision_incline");
  char xml[1024];
  std::snprintf(xml, sizeof xml, R"(<scene>
  <simulation timestep="0.001" fps="24" startFrame="1" endFrame="49"/>
  <plane name="slope" point="0 0 0" normal="%.17g %.17g 0" friction="%g"/>
  <cloth name="c" grid="4 4" size="0.1 0.1" rotate="0 0 %.17g" translate="%.17g %.17g 0" friction="%g">
    <density value="2"/><stiffness value="50"/><damping value="0.01"/><thickness value="%g"/>
  </cloth></scene>)", n.x(), n.y(), mu_plane, deg, h * n.x(), h * n.y(), mu_cloth, h);
  write_text(dir / "s.xml", xml);
  auto sc = load_collision_scene(dir / "s.xml");
  const Vec3 start = centroid(sc.built.state);
  Vec3 end = start;
  run_frames(sc, [&](int, const Model&, const State& s, const Workspace&) { end = centroid(s); });
  return (end - start).norm();
}

TEST_CASE("incline: sticks below tan theta = mu, slides by the Coulomb closed form above it") {
  // 48 frames at 24 fps = 2 s.
  CHECK(incline_travel(0.45) < 1e-3);
  const Real tan_theta = 0.55, theta = std::atan(tan_theta), t = 2.0;
  const Real expected = 0.5 * 9.81 * (std::sin(theta) - 0.5 * std::cos(theta)) * t * t;  // 0.86 m
  CHECK(incline_travel(tan_theta) == doctest::Approx(expected).epsilon(0.05));
}

TEST_CASE("friction combine: a frictionless plane under a mu 0.6 cloth lets it slide down 15 degrees freely") {
  // Geometric mean sqrt(0.6 * 0) = 0: the Coulomb closed form with mu 0, a = g sin 15 deg, over 2 s. (A mean
  // of 0.3 would exceed tan 15 = 0.27 and hold the patch.)
  const Real theta = 15 * M_PI / 180, t = 2.0;
  CHECK(incline_travel(std::tan(theta), 0.6, 0) == doctest::Approx(0.5 * 9.81 * std::sin(theta) * t * t).epsilon(0.03));
  // sqrt(0.6 * 0.1) = 0.245 < tan 15: it slides at g (sin - 0.245 cos); a mean (0.35) would hold it.
  const Real mu = std::sqrt(0.06);
  CHECK(incline_travel(std::tan(theta), 0.6, 0.1) ==
        doctest::Approx(0.5 * 9.81 * (std::sin(theta) - mu * std::cos(theta)) * t * t).epsilon(0.05));
}

TEST_CASE("restitution: a flat cloth leaves the ground with the set ratio of normal speeds") {
  const auto dir = scratch_dir("collision_restitution");
  write_text(dir / "s.xml", R"(<scene>
  <simulation timestep="0.0001" fps="100" startFrame="1" endFrame="40"/>
  <plane name="ground" point="0 0 0" normal="0 1 0" friction="0"/>
  <cloth name="c" grid="4 4" size="0.1 0.1" translate="0 0.2 0" friction="0" restitution="0.5">
    <density value="2"/><stiffness value="50"/><damping value="0.01"/><thickness value="0.005"/>
  </cloth></scene>)");
  auto sc = load_collision_scene(dir / "s.xml");
  const Model& m = sc.built.model;
  State s = sc.built.state, next = s;
  Workspace ws = make_workspace(m, sc.built.options);
  Real impact = 0, rebound = 0;
  for (int k = 0; k < 3000 && rebound == 0; ++k) {
    const Real before = centroid_v(s);
    step(m, sc.built.options, s, next, ws, sc.built.options.dt);
    std::swap(s, next);
    const Real after = centroid_v(s);
    if (before < 0 && after > 0) { impact = -before; rebound = after; }
  }
  REQUIRE(impact > 1.5);  // fell ~0.2 m: sqrt(2 g 0.195) = 1.96 m/s
  CHECK(rebound / impact == doctest::Approx(0.5).epsilon(0.1));
}

TEST_CASE("tunnelling: a sphere crossing a pinned sheet at 20 m/s pushes it, no vertex ends on the wrong side") {
  // The sphere (r = 0.15 m) moves down at 20 m/s (0.2 m per frame at 100 fps, 2 cm per step: four times the
  // thickness) from 0.4 m above the sheet until its centre is 0.1 m below it, then stops.
  const auto dir = scratch_dir("collision_tunnel");
  const Real r = 0.15, stop = -0.1;
  for (int f = 1; f <= 12; ++f) {
    char name[64];
    std::snprintf(name, sizeof name, "ball.%04d.obj", f);
    write_text(dir / name, test::sphere_obj(Vec3(0, std::max(0.4 - 0.2 * (f - 1), stop), 0), r, 16, 32));
  }
  const int n = 24;
  std::string pins;
  for (int i = 0; i < n; ++i)
    pins += std::to_string(i) + " " + std::to_string((n - 1) * n + i) + " " + std::to_string(n * i) + " " +
            std::to_string(n * i + n - 1) + " ";
  write_text(dir / "s.xml", R"(<scene>
  <simulation timestep="0.001" fps="100" startFrame="1" endFrame="12"/>
  <static name="ball" sequence="ball.####.obj" friction="0.8"/>
  <cloth name="c" grid="24 24" size="0.8 0.8" friction="0.8">
    <density value="0.5"/><stiffness value="100"/><damping value="0.01"/><thickness value="0.005"/>
    <pins vertices=")" + pins + R"("/>
  </cloth></scene>)");
  auto sc = load_collision_scene(dir / "s.xml");
  REQUIRE(sc.built.model.collision.colliders[0].closed);
  Index inside = 0, above = 0;
  Real lowest = 0;
  run_frames(sc, [&](int f, const Model& m, const State& s, const Workspace& ws) {
    inside += count_inside(m, s.x, ws.collision, 0);
    // Once the sphere has passed the sheet's plane, the cloth under it must be below its centre.
    const Real centre = std::max(0.4 - 0.2 * (f - 1), stop);
    for (const Vec3& p : s.x) {
      lowest = std::min(lowest, p.y());
      if (centre < -r / 2 && p.x() * p.x() + p.z() * p.z() < r * r / 4 && p.y() > centre) ++above;
    }
  });
  CHECK(inside == 0);
  CHECK(above == 0);
  CHECK(lowest < stop - r);  // pushed down with the sphere, whose bottom ends at -0.25 m
}

namespace {
const char* fold_scene = R"(<scene>
  <simulation timestep="0.0005" fps="24" startFrame="1" endFrame="20" collisionIterations="3" broadPhase="%s"/>
  <forces><airDamping value="0.2"/></forces>
  <plane name="ground" point="0 0 0" normal="0 1 0" friction="0.6"/>
  <cloth name="c" grid="12 12" size="0.4 0.4" rotate="75 0 0" translate="0 0.21 0" friction="0.3"
         selfCollision="true">
    <density value="0.5"/><stiffness value="100" bend="0.05"/><thickness value="0.01"/>
  </cloth></scene>)";

test::LoadedCollisionScene load_fold(const char* broad) {
  const auto dir = scratch_dir(std::string("collision_fold_") + broad);
  char xml[2048];
  std::snprintf(xml, sizeof xml, fold_scene, broad);
  write_text(dir / "s.xml", xml);
  return load_collision_scene(dir / "s.xml");
}
}  // namespace

TEST_CASE("self-collision: in the fold scene no two non-adjacent triangles intersect at any frame") {
  auto sc = load_fold("hash");
  Index crossings = 0;
  Real lowest_top = 1;
  run_frames(sc, [&](int, const Model& m, const State& s, const Workspace&) {
    crossings += count_intersecting_triangles(m, s.x);
    Real top = -1;
    for (const Vec3& p : s.x) top = std::max(top, p.y());
    lowest_top = std::min(lowest_top, top);
  });
  CHECK(crossings == 0);
  CHECK(lowest_top < 0.2);  // it did fall over: the sheet started 0.4 m tall
}


TEST_CASE("hash, BVH and brute force find the same proximities on random configurations") {
  const auto dir = scratch_dir("collision_broad");
  write_text(dir / "ball.obj", test::sphere_obj(Vec3(0, 0, 0), 0.2, 8, 16));
  for (const char* broad : {"hash", "bvh"}) {
    char xml[1024];
    std::snprintf(xml, sizeof xml, R"(<scene>
  <simulation broadPhase="%s"/>
  <static name="ball" obj="ball.obj"/>
  <cloth name="c" grid="20 20" size="0.6 0.6" selfCollision="true"><thickness value="0.02"/></cloth>
</scene>)", broad);
    write_text(dir / (std::string(broad) + ".xml"), xml);
  }
  auto hash = load_collision_scene(dir / "hash.xml");
  auto bvh = load_collision_scene(dir / "bvh.xml");
  std::mt19937 rng(5);
  std::uniform_real_distribution<Real> u(-0.25, 0.25), small(-0.01, 0.01);
  std::size_t total = 0, kinds[4] = {};
  for (int trial = 0; trial < 4; ++trial) {
    // A crumpled sheet (heights scattered over 8 cm) draped near a sphere: many vertex-triangle and edge-edge
    // pairs within the thickness, against both the cloth and the collider.
    State in = hash.built.state, out = in;
    for (std::size_t i = 0; i < in.x.size(); ++i) {
      in.x[i] += Vec3(0.2 * small(rng), 0.18 + 0.04 * trial + u(rng) * 0.16, 0.2 * small(rng));
      out.x[i] = in.x[i] + Vec3(small(rng), small(rng), small(rng));
    }
    Workspace wh = make_workspace(hash.built.model, hash.built.options);
    Workspace wb = make_workspace(bvh.built.model, bvh.built.options);
    build_broad_phase(hash.built.model, in, out, wh.collision);
    build_broad_phase(bvh.built.model, in, out, wb.collision);
    const auto by_hash = list_proximities(hash.built.model, in, out, wh.collision, BroadMode::hash);
    const auto by_bvh = list_proximities(bvh.built.model, in, out, wb.collision, BroadMode::bvh);
    const auto by_brute = list_proximities(hash.built.model, in, out, wh.collision, BroadMode::brute);
    CHECK(by_hash == by_brute);
    CHECK(by_bvh == by_brute);
    // The cloth's side alone (the cloth-cloth holds' walk) finds exactly the cloth-cloth pairs of the full walk.
    std::vector<std::array<Index, 3>> cloth_pairs;
    for (const auto& pair : by_brute)
      if (pair[0] == Index(ContactKind::cloth_edges) ||
          (pair[0] == Index(ContactKind::vertex_triangle) && pair[2] < hash.built.model.tri_count))
        cloth_pairs.push_back(pair);
    CHECK(!cloth_pairs.empty());
    CHECK(list_proximities(hash.built.model, in, out, wh.collision, BroadMode::hash_cloth) == cloth_pairs);
    CHECK(list_proximities(bvh.built.model, in, out, wb.collision, BroadMode::bvh_cloth) == cloth_pairs);
    total += by_brute.size();
    for (const auto& pair : by_brute) ++kinds[pair[0]];
  }
  CHECK(total > 100);
  // Every kind of pair occurs: cloth vertex-triangle, edge-edge, collider vertex-cloth triangle, cloth
  // edge-collider edge (so the cloth side's walk left collider pairs out).
  for (int k = 0; k < 4; ++k) CHECK(kinds[k] > 0);
}

TEST_CASE("a cloth blown up within a step: the hash enlarges its cell to stay within budget, same proximities") {
  // A diverging cloth swells its swept boxes before the frame's divergence check can stop the run; at the
  // model's cell one box would cover ~1e20 cells (11.8 GB of entries were seen before the process was killed).
  const auto dir = scratch_dir("collision_blown");
  write_text(dir / "s.xml", R"(<scene><simulation broadPhase="hash"/>
  <cloth name="c" grid="20 20" size="0.6 0.6" selfCollision="true"><thickness value="0.02"/></cloth>
</scene>)");
  auto sc = load_collision_scene(dir / "s.xml");
  const Model& m = sc.built.model;
  std::mt19937 rng(9);
  std::uniform_real_distribution<Real> small(-0.01, 0.01);
  State in = sc.built.state, out = in;
  for (std::size_t i = 0; i < in.x.size(); ++i) {
    in.x[i] += Vec3(0.2 * small(rng), 4 * small(rng), 0.2 * small(rng));
    out.x[i] = in.x[i] + Vec3(small(rng), small(rng), small(rng));
  }
  out.x[57] += Vec3(3e4, -2e4, 1e4);  // one vertex flung 37 km within the step
  Workspace ws = make_workspace(m, sc.built.options);
  build_broad_phase(m, in, out, ws.collision);
  const Index prims = Index(m.collision.prim.size());
  INFO("entries " << ws.collision.hash.entry_count << " for " << prims << " prims");
  CHECK(ws.collision.hash.entry_count <= 64 * prims + 65536);
  CHECK(ws.collision.hash.inv_cell < 1 / m.collision.cell_size);
  const auto by_hash = list_proximities(m, in, out, ws.collision, BroadMode::hash);
  const auto by_brute = list_proximities(m, in, out, ws.collision, BroadMode::brute);
  CHECK(by_hash == by_brute);
  CHECK(by_brute.size() > 50);
}

TEST_CASE("a scene without colliders and self-collision builds nothing for collisions") {
  const auto dir = scratch_dir("collision_none");
  write_text(dir / "s.xml", R"(<scene><cloth name="c" grid="4 4"/></scene>)");
  auto sc = load_collision_scene(dir / "s.xml");
  const Model& m = sc.built.model;
  CHECK_FALSE(m.collision.enabled);
  CHECK(m.collision.prim.empty());
  CHECK(m.collision.particle_cloth.empty());
  CHECK(make_workspace(m, sc.built.options).collision.acc_count.empty());
}

namespace {
// A thin closed bar along z (a triangular prism 4 mm wide, 4 mm tall, ridge at y = 0, x = 0, 1 m long) under a
// coarse 4 x 4 cloth whose vertices sit at x = +-0.1 and +-0.3: no cloth vertex ever comes near the bar's
// triangles, so only the cloth edges meeting the ridge edge (edge-edge CCD) can hold the cloth up.
const char* bar_obj = R"(v -0.002 -0.004 -0.5
v 0.002 -0.004 -0.5
v 0 0 -0.5
v -0.002 -0.004 0.5
v 0.002 -0.004 0.5
v 0 0 0.5
f 1 3 2
f 4 5 6
f 1 2 5
f 1 5 4
f 2 3 6
f 2 6 5
f 3 1 4
f 3 4 6
)";

test::LoadedCollisionScene load_bar(const char* broad) {
  const auto dir = scratch_dir(std::string("collision_bar_") + broad);
  write_text(dir / "bar.obj", bar_obj);
  char xml[1024];
  std::snprintf(xml, sizeof xml, R"(<scene>
  <simulation timestep="0.001" fps="50" startFrame="1" endFrame="16" broadPhase="%s"/>
  <static name="bar" obj="bar.obj" friction="0.9"/>
  <cloth name="c" grid="4 4" size="0.6 0.6" translate="0 0.05 0" friction="0.9">
    <density value="0.5"/><stiffness value="100"/><damping value="0.01"/><thickness value="0.005"/>
  </cloth></scene>)", broad);
  write_text(dir / "s.xml", xml);
  return load_collision_scene(dir / "s.xml");
}

// Cloth edges that span the bar's plane x = 0 within its length and pass it below the ridge (y < 0): on the
// wrong side of the ridge edge, inside or under the bar. Also the lowest such crossing height.
Index edges_under_ridge(const Model& m, const State& s, Real& lowest) {
  Index wrong = 0;
  for (Index t = 0; t < m.tri_count; ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3& a = s.x[m.tri_index[3 * t + k]];
      const Vec3& b = s.x[m.tri_index[3 * t + (k + 1) % 3]];
      if ((a.x() < 0) == (b.x() < 0)) continue;
      const Vec3 p = a + (0 - a.x()) / (b.x() - a.x()) * (b - a);
      if (std::abs(p.z()) > 0.5) continue;
      lowest = std::min(lowest, p.y());
      if (p.y() < 0) ++wrong;
    }
  return wrong;
}
}  // namespace

TEST_CASE("edge-edge CCD: a coarse cloth falls onto a thin bar between its vertices and stays on the ridge") {
  for (const char* broad : {"hash", "bvh"}) {
    const std::string phase = broad;
    CAPTURE(phase);
    auto sc = load_bar(broad);
    REQUIRE(sc.built.model.collision.colliders[0].closed);
    Index wrong = 0;
    Real lowest_crossing = 1, lowest_vertex = 1;
    run_frames(sc, [&](int, const Model& m, const State& s, const Workspace&) {
      wrong += edges_under_ridge(m, s, lowest_crossing);
      for (const Vec3& p : s.x) lowest_vertex = std::min(lowest_vertex, p.y());
    });
    CHECK(wrong == 0);
    // Held at the thickness (5 mm) over the ridge by the edge-edge proximity against the collider's edges; with
    // the continuous pass alone the edges sank to 0.46 mm.
    CHECK(lowest_crossing > 0.99 * 0.005);
    // The cloth did land and drape: its outer vertices hang below the ridge (a free fall over the 0.3 s would
    // take it 0.44 m down; held at the middle, the sides fold down by less than their 0.3 m width).
    CHECK(lowest_vertex < -0.05);
    CHECK(lowest_vertex > -0.31);
  }
}

TEST_CASE("edge-edge CCD: a strip's edge swept through another strip within one step is sent back") {
  // Strip B lies flat at y = 0 over x in [0, 0.2], z in [-0.1, 0.1]. Strip A stands upright in the plane z = 0,
  // its bottom edge from x = -0.1 to 0.3 at y = 0.01, and drops 2 cm within one step: the bottom edge crosses
  // B's three edges at x = 0, 0.1 (the diagonal) and 0.2 while no vertex passes through a triangle.
  const auto dir = scratch_dir("collision_strips");
  write_text(dir / "s.xml", R"(<scene>
  <simulation timestep="0.001" fps="100" startFrame="1" endFrame="2" collisionIterations="2"/>
  <cloth name="b" grid="2 2" size="0.2 0.2" translate="0.1 0 0" selfCollision="true">
    <thickness value="0.001"/></cloth>
  <cloth name="a" grid="2 2" size="0.4 0.2" rotate="90 0 0" translate="0.1 0.11 0" selfCollision="true">
    <thickness value="0.001"/></cloth>
</scene>)");
  std::vector<Vec3> result[2];
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    auto sc = load_collision_scene(dir / "s.xml");
    const Model& m = sc.built.model;
    const State in = sc.built.state;
    const ClothInfo& a = m.cloths[1];
    REQUIRE(a.particle_end - a.particle_begin == 4);
    Real bottom = 1;
    for (Index i = a.particle_begin; i < a.particle_end; ++i) bottom = std::min(bottom, in.x[i].y());
    REQUIRE(bottom == doctest::Approx(0.01));
    const Real h = 0.001;
    State out = in;
    for (Index i = a.particle_begin; i < a.particle_end; ++i) {
      out.x[i].y() -= 0.02;
      out.v[i] = Vec3(0, -0.02 / h, 0);
    }
    REQUIRE(count_intersecting_triangles(m, out.x) > 0);  // uncorrected, A's bottom edge lies through B
    Workspace ws = make_workspace(m, sc.built.options);
    collide(m, in, out, ws, h);
    CHECK(count_intersecting_triangles(m, out.x) == 0);
    // Both sides moved: A's bottom edge ends above B's plane, which was pushed down.
    Real a_bottom = 1, b_top = -1;
    for (Index i = a.particle_begin; i < a.particle_end; ++i) a_bottom = std::min(a_bottom, out.x[i].y());
    for (Index i = m.cloths[0].particle_begin; i < m.cloths[0].particle_end; ++i) b_top = std::max(b_top, out.x[i].y());
    CHECK(a_bottom > b_top);
    CHECK(b_top < 0);
    result[threads - 1] = out.x;
  }
  CHECK(std::memcmp(result[0].data(), result[1].data(), result[0].size() * sizeof(Vec3)) == 0);
}

TEST_CASE("collision runs give the same bytes at 1 and 2 threads: self-collision and a collider's edges, hash and BVH") {
  for (auto load : {load_fold, load_bar})
    for (const char* broad : {"hash", "bvh"}) {
      std::vector<Vec3> result[2];
      for (int t = 1; t <= 2; ++t) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, t);
        auto sc = load(broad);
        run_frames(sc, [&](int, const Model&, const State& s, const Workspace&) { result[t - 1] = s.x; });
      }
      REQUIRE(result[0].size() == result[1].size());
      CHECK(std::memcmp(result[0].data(), result[1].data(), result[0].size() * sizeof(Vec3)) == 0);
    }
}

TEST_CASE("--stats check for open collider meshes: cloth triangles crossing a collider triangle, counted by hand") {
  // An open collider, one triangle in y = 0 covering x + z <= 1; an upright 2-triangle cloth in the plane
  // z = 0.3 over x in [0.1, 0.5], y in [-0.1, 0.1] cuts through it: both cloth triangles cross it (2 pairs).
  // Lifted by 0.2 m it crosses nothing.
  const auto dir = scratch_dir("collision_open_crossings");
  write_text(dir / "floor.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 3 2\n");
  for (const char* y : {"0", "0.2"}) {
    write_text(dir / "s.xml", std::string(R"(<scene>
  <static name="floor" obj="floor.obj"/>
  <cloth name="c" grid="2 2" size="0.4 0.2" rotate="90 0 0" translate="0.3 )") + y + R"( 0.3"/></scene>)");
    auto sc = load_collision_scene(dir / "s.xml");
    const Model& m = sc.built.model;
    REQUIRE_FALSE(m.collision.colliders[0].closed);
    const Workspace ws = make_workspace(m, sc.built.options);
    CHECK(count_inside(m, sc.built.state.x, ws.collision, 0) == 0);  // not defined for an open mesh
    CHECK(count_collider_crossings(m, sc.built.state.x, ws.collision, 0) == (std::string(y) == "0" ? 2 : 0));
  }
}
