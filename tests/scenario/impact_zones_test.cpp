// Rigid impact zones (systems/collision/impact_zones.h; Provot 1997, Bridson, Fedkiw & Anderson 2002 §6.3): the union
// of crossing pairs into zones, the rigid fit of a zone against its closed-form invariants (momenta, distances, the
// collider's motion), and scenes where the averaged responses of the continuous pass leave crossings that the zones
// remove.
#include <doctest/doctest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <random>

#include "systems/collision/collide.h"
#include "systems/collision/collision_check.h"
#include "systems/collision/continuous_pairs.h"
#include "systems/collision/contacts.h"
#include "systems/collision/reach_grid.h"
#include "systems/collision/impact_zones.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;
using clothsim::test::load_collision_scene;
using clothsim::test::scratch_dir;
using clothsim::test::write_text;

namespace {

// `particles` free particles of masses 10, 20, 30 ... g and `collider` collider vertices, with zone scratch for
// them all: the model a zone needs, without a scene.
struct ZoneFixture {
  Model m;
  CollisionScratch s;
  State in, out;
  ZoneFixture(int particles, int collider) {
    m.particle_count = particles;
    for (int i = 0; i < particles; ++i) m.particle_inv_mass.push_back(1 / (0.01 * (i + 1)));
    m.collision.mesh_vertex_count = collider;
    s.collider_x0.assign(collider, Vec3::Zero());
    s.collider_x1.assign(collider, Vec3::Zero());
    const std::size_t nodes = std::size_t(particles) + collider;
    s.zones.parent.resize(nodes);
    s.zones.flag.assign(nodes, 0);
    s.zones.slot.assign(nodes, -1);
    s.zones.offset.assign(nodes + 1, 0);
    s.zones.member.resize(nodes);
    in.x.assign(particles, Vec3::Zero());
    in.v = in.x;
    out = in;
  }
  Real mass(int i) const { return 1 / m.particle_inv_mass[i]; }
  Vec3 momentum(const State& st) const {
    Vec3 p = Vec3::Zero();
    for (int i = 0; i < m.particle_count; ++i) p += mass(i) * st.v[i];
    return p;
  }
  Vec3 center(const State& st) const {
    Vec3 c = Vec3::Zero();
    Real total = 0;
    for (int i = 0; i < m.particle_count; ++i) {
      c += mass(i) * st.x[i];
      total += mass(i);
    }
    return c / total;
  }
  Vec3 angular_momentum(const State& st) const {
    const Vec3 c = center(st);
    Vec3 l = Vec3::Zero();
    for (int i = 0; i < m.particle_count; ++i) l += mass(i) * (st.x[i] - c).cross(st.v[i]);
    return l;
  }
};

}  // namespace

TEST_CASE("impact zones: pairs sharing a node form one zone whose root is its smallest node, members ascending") {
  ZoneFixture f(8, 0);
  reset_zones(f.s.zones);
  const Index a[4] = {6, 2, 7, 5}, b[4] = {3, 1, 0, 4}, c[4] = {5, 3, 6, 2};
  CHECK(add_zone_pair(f.s.zones, a, 4) == 3);
  CHECK(add_zone_pair(f.s.zones, b, 4) == 3);
  CHECK(add_zone_pair(f.s.zones, c, 4) == 1);  // joins the two zones through 5 and 3 (or 2, 6): one link
  gather_zones(f.s.zones);
  REQUIRE(f.s.zones.zone_count == 1);
  CHECK(f.s.zones.offset[1] == 8);
  for (Index k = 0; k < 8; ++k) CHECK(f.s.zones.member[k] == k);
  for (Index k = 0; k < 8; ++k) CHECK(f.s.zones.parent[k] == 0);
}

TEST_CASE("impact zones: a free zone's rigid fit keeps its linear and angular momentum and its vertices' distances") {
  ZoneFixture f(6, 0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Real h = 1e-3;
  for (int i = 0; i < 6; ++i) {
    f.in.x[i] = 0.1 * Vec3(u(rng), u(rng), u(rng));
    f.out.x[i] = f.in.x[i] + h * Vec3(u(rng), u(rng), u(rng));  // an arbitrary (non-rigid) motion over the step
    f.out.v[i] = Vec3(u(rng), u(rng), u(rng));
  }
  const Vec3 p_before = f.momentum(f.out), l_before = f.angular_momentum(f.out);
  // The centre of mass's displacement: the mass-weighted mean of the members' displacements.
  const Vec3 expected_center = f.center(f.out);
  reset_zones(f.s.zones);
  const Index first[4] = {0, 1, 2, 3}, second[4] = {3, 4, 5, 0};
  add_zone_pair(f.s.zones, first, 4);
  add_zone_pair(f.s.zones, second, 4);
  gather_zones(f.s.zones);
  REQUIRE(f.s.zones.zone_count == 1);
  rigidify_zones(f.m, f.in, f.out, f.s, h);
  const Vec3 p_after = f.momentum(f.out), l_after = f.angular_momentum(f.out);
  INFO("P " << p_before.transpose() << " -> " << p_after.transpose() << ", L " << l_before.transpose() << " -> "
            << l_after.transpose());
  CHECK((p_after - p_before).norm() <= 1e-14 * p_before.norm() + 1e-16);
  CHECK((l_after - l_before).norm() <= 1e-12 * l_before.norm());
  CHECK((f.center(f.out) - expected_center).norm() < 1e-15);
  Real worst = 0;
  for (int i = 0; i < 6; ++i)
    for (int j = i + 1; j < 6; ++j)
      worst = std::max(worst, std::abs((f.out.x[i] - f.out.x[j]).norm() - (f.in.x[i] - f.in.x[j]).norm()));
  CHECK(worst < 1e-15);
  // The momenta and distances are not kept by accident: the motion before the fit was not rigid.
  Real spread = 0;
  for (int i = 0; i < 6; ++i) spread = std::max(spread, (f.out.v[i] - (p_after / 0.21)).norm());
  CHECK(spread > 0.1);
}

TEST_CASE("impact zones: a zone touching a collider takes the collider's motion (collider vertices: infinite mass)") {
  // Three collider vertices translated by d over the step, two cloth particles moving anywhere: the particles
  // end where the translation takes them from their start, at the collider's velocity d / h.
  ZoneFixture f(2, 3);
  const Real h = 2e-3;
  const Vec3 d(0.004, -0.001, 0.002);
  f.s.collider_x0 = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0, 0.1)};
  for (int k = 0; k < 3; ++k) f.s.collider_x1[k] = f.s.collider_x0[k] + d;
  f.in.x = {Vec3(0.02, 0.01, 0.03), Vec3(0.05, 0.012, 0.02)};
  f.out.x = {f.in.x[0] + Vec3(0, -0.01, 0), f.in.x[1] + Vec3(0.003, 0.002, 0)};
  f.out.v = {Vec3(0, -5, 0), Vec3(1.5, 1, 0)};
  reset_zones(f.s.zones);
  const Index pair[4] = {0, 2, 3, 4};  // particle 0 against collider vertices 0, 1, 2 (nodes 2, 3, 4)
  const Index edge[4] = {0, 1, 3, 4};
  add_zone_pair(f.s.zones, pair, 4);
  add_zone_pair(f.s.zones, edge, 4);
  gather_zones(f.s.zones);
  REQUIRE(f.s.zones.zone_count == 1);
  rigidify_zones(f.m, f.in, f.out, f.s, h);
  for (int i = 0; i < 2; ++i) {
    CHECK((f.out.x[i] - (f.in.x[i] + d)).norm() < 1e-15);
    CHECK((f.out.v[i] - d / h).norm() < 1e-12);
  }
}

namespace {

// Three small sheets stacked 1 cm apart (4 mm thick, colliding with each other), moved within one 1 ms step
// so that they pass through each other: the lowest up 2 cm, the middle down 4 cm, the top up 1.5 cm, every
// vertex jittered by up to 2 mm sideways and 4 mm vertically (a random, seeded, non-rigid motion). The start
// is clean (the sheets are 1 cm apart); the motion, uncorrected, ends with the sheets swapped through each other.
struct ThroughRun {
  Index crossings = 0;  // intersecting triangle pairs after the collide stage
  std::vector<Vec3> x;  // positions after it
  ZoneFigures zones;    // the stage's zone figures
};

ThroughRun sheets_through(int zone_iterations) {
  const auto dir = scratch_dir("zones_through_" + std::to_string(zone_iterations));
  char xml[2048];
  std::snprintf(xml, sizeof xml, R"(<scene>
  <simulation timestep="0.001" fps="100" startFrame="1" endFrame="2" collisionIterations="2"
              impactZoneIterations="%d"/>
  <cloth name="a" grid="6 6" size="0.2 0.2"><thickness value="0.004"/></cloth>
  <cloth name="b" grid="7 7" size="0.2 0.2" translate="0.011 0.01 0.007"><thickness value="0.004"/></cloth>
  <cloth name="c" grid="5 5" size="0.2 0.2" translate="-0.013 0.02 0.005"><thickness value="0.004"/></cloth>
</scene>)", zone_iterations);
  write_text(dir / "s.xml", xml);
  auto sc = load_collision_scene(dir / "s.xml");
  const Model& m = sc.built.model;
  const State in = sc.built.state;
  State out = in;
  std::mt19937 rng(2);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Real h = 0.001, rise[3] = {0.02, -0.04, 0.015};
  for (int k = 0; k < 3; ++k)
    for (Index i = m.cloths[k].particle_begin; i < m.cloths[k].particle_end; ++i) {
      out.x[i] = in.x[i] + Vec3(0.002 * u(rng), rise[k] + 0.004 * u(rng), 0.002 * u(rng));
      out.v[i] = (out.x[i] - in.x[i]) / h;
    }
  REQUIRE(count_intersecting_triangles(m, in.x) == 0);
  Workspace ws = make_workspace(m, sc.built.options);
  const CollideCounts counts = collide(m, in, out, ws, h);
  ThroughRun r;
  r.crossings = count_intersecting_triangles(m, out.x);
  r.x = out.x;
  r.zones = counts.zones;
  return r;
}

// The same under `threads` threads (an arena of that many, even above the machine's cores).
ThroughRun sheets_through_each_other(int zone_iterations, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  tbb::task_arena arena(threads);
  ThroughRun r;
  arena.execute([&] { r = sheets_through(zone_iterations); });
  return r;
}

}  // namespace

TEST_CASE("impact zones: sheets driven through each other in one step end with no crossing (24 without zones)") {
  // Two continuous passes respond to every crossing, but each vertex gets the average of its responses, so the
  // sheets end tangled: 24 intersecting triangle pairs (53 while edge pairs that passed within the thickness
  // without meeting were also sent back, along the lines' cross product). The zones merge the pairs still
  // crossing and move each zone rigidly from its clean start: none is left, in two passes (the second finds
  // nothing), with one zone of 19 vertices (3 zones of 41 in all before).
  const ThroughRun off = sheets_through_each_other(0, 2);
  CHECK(off.crossings == 24);
  CHECK(off.zones.steps == 0);
  const ThroughRun on = sheets_through_each_other(16, 2);
  CHECK(on.crossings == 0);
  CHECK(on.zones.steps == 1);
  CHECK(on.zones.unresolved == 0);
  CHECK(on.zones.passes == 2);
  CHECK(on.zones.zones == 1);
  CHECK(on.zones.zone_nodes == 19);
  MESSAGE("zones " << on.zones.zones << ", vertices in them " << on.zones.zone_nodes << ", largest "
                   << on.zones.largest << " of " << on.x.size());
}

TEST_CASE("impact zones: the same bytes at 1, 2 and 3 threads") {
  const ThroughRun one = sheets_through_each_other(16, 1);
  REQUIRE(one.zones.zones > 0);
  for (int threads : {2, 3}) {
    const ThroughRun other = sheets_through_each_other(16, threads);
    CAPTURE(threads);
    REQUIRE(other.x.size() == one.x.size());
    CHECK(std::memcmp(other.x.data(), one.x.data(), one.x.size() * sizeof(Vec3)) == 0);
    CHECK(other.zones.zone_nodes == one.zones.zone_nodes);
  }
}

TEST_CASE("the Kick body's fastest frames (shared data: skipped without it): no crossing from frame 52 to 66" * doctest::test_suite("slow")) {
  const auto seq = test::kick_sequence();
  if (seq.empty()) {
    MESSAGE("shared data not found (../shared/data): skipped");
    return;
  }
  // The drop of docs/performance.md ("Rigid impact zones") takes 60 frames to reach the kick; this window starts
  // the same sheet (self-colliding, 6 mm thick) at rest 1.5 cm over the head at frame 52, so it lands while the
  // body moves 0.23-0.37 m a frame (frames 52-63: the kick, the fastest of the run) and is caught between the
  // kicking leg and the body. With impactZoneIterations="0" the same window has 10 crossing pairs at frame 60,
  // 4 at 64, 428 at 65 and 671 at 66, the sheet left 0.03 mm from the body.
  const auto dir = scratch_dir("zones_kick_window");
  write_text(dir / "s.xml", test::kick_scene(seq, 52, 66, Vec3(0.26, 1.179, 0.77), R"(selfCollision="true")"));
  auto sc = load_collision_scene(dir / "s.xml");
  Index penetrations = 0;
  Real nearest = 1e9;
  std::int64_t zone_steps = 0;
  test::run_frames(sc, [&](int f, const Model& m, const State& s, const Workspace& ws, const sim::FrameReport& r) {
    penetrations += count_collider_crossings(m, s.x, ws.collision, 0) + count_intersecting_triangles(m, s.x);
    if (f > 53) nearest = std::min(nearest, min_collider_distance(m, s.x, ws.collision, 0));
    zone_steps += r.steps.counts.zones.steps;
  });
  CHECK(penetrations == 0);
  CHECK(zone_steps > 100);  // the zones did the work: they ran in hundreds of the 1,400 steps
  // Held apart from the body, where without zones it was 0.03 mm: 1.7 mm. It was 3 mm and more while edge pairs
  // that only passed within the thickness were also sent back, along the lines' cross product.
  CHECK(nearest > 0.25 * 0.006);
  MESSAGE("nearest cloth vertex to the body from frame 54 on: " << nearest << " m; steps with zones " << zone_steps);
}

namespace {

// Two 40 x 40 sheets 1 cm apart (cloths a and b, 5 mm thick), colliding with each other.
sim::LoadedScene two_sheets(const char* name) {
  const auto dir = scratch_dir(name);
  write_text(dir / "s.xml", R"(<scene>
  <cloth name="a" grid="40 40" size="0.6 0.6"><thickness value="0.005"/></cloth>
  <cloth name="b" grid="40 40" size="0.6 0.6" translate="0.007 0.01 0.004"><thickness value="0.005"/></cloth>
</scene>)");
  auto sc = load_collision_scene(dir / "s.xml");
  REQUIRE(sc.built.model.particle_count == 3200);
  return sc;
}

// Crumples both sheets by up to 2 mm and moves the upper one (or, with `patch`, its 10 x 10 vertices from row and
// column 10) down through the lower over the step: cloth-cloth crossings everywhere, or in one patch.
void crumple(const Model& m, std::mt19937& rng, State& in, State& out, bool patch = false) {
  std::uniform_real_distribution<Real> small(-0.002, 0.002);
  for (Index i = 0; i < m.particle_count; ++i) {
    const Index row = (i % 1600) / 40, col = i % 40;
    const bool plunges = i >= 1600 && (!patch || (row >= 10 && row < 20 && col >= 10 && col < 20));
    in.x[i].y() += small(rng);
    out.x[i] = in.x[i] + Vec3(small(rng), plunges ? small(rng) - 0.02 : small(rng), small(rng));
  }
}

}  // namespace

TEST_CASE("the zones' later passes find the same pairs walking only the elements near a zone") {
  // Two crumpled sheets, the upper one passing down through the lower over the step (cloth-cloth crossings
  // everywhere), with three 5 x 5 patches of the lower taken as zones: the pairs touching a zone member are the
  // same whether the walk visits every element or only those whose swept box meets a reach box
  // (gather_reach_boxes), and the reach skips most elements. The upper sheet's vertices and edges that cross a
  // member's triangle are found only through the reach's growth by the largest triangle box.
  auto sc = two_sheets("zone_reach");
  const Model& m = sc.built.model;
  std::mt19937 rng(17);
  std::uniform_int_distribution<Index> corner(0, 34);
  Index pairs = 0;
  for (int trial = 0; trial < 4; ++trial) {
    State in = sc.built.state, out = in;
    crumple(m, rng, in, out);
    Workspace ws = make_workspace(m, sc.built.options);
    CollisionScratch& s = ws.collision;
    build_broad_phase(m, in, out, s);
    ZoneScratch& z = s.zones;
    reset_zones(z);
    for (int zone = 0; zone < 3; ++zone) {
      const Index ci = corner(rng), cj = corner(rng), root = 40 * cj + ci;
      for (Index j = cj; j < cj + 5; ++j)
        for (Index i = ci; i < ci + 5; ++i) {
          z.flag[40 * j + i] |= zone_member;
          z.parent[40 * j + i] = root;
        }
    }
    auto member = [&](const Index* p, int count) {
      for (int k = 0; k < count; ++k)
        if (z.flag[p[k]] & zone_member) return true;
      return false;
    };
    find_crossings(m, in, out, s, broad_mode(m.collision), member);
    const auto everywhere = list_contacts(s);
    gather_reach_boxes(m, in, out, s, z);
    CHECK(z.reach_box.size() <= 3);
    std::atomic<Index> walked{0};
    auto near = [&](const Aabb& q) {
      if (!near_a_zone(z, q)) return false;
      walked.fetch_add(1);
      return true;
    };
    find_crossings(m, in, out, s, broad_mode(m.collision), member, near);
    const Index elements = m.particle_count + Index(m.collision.edge_a.size());
    INFO("trial " << trial << ": " << everywhere.size() << " pairs, " << walked.load() << " of " << elements
                  << " elements walked");
    CHECK(list_contacts(s) == everywhere);
    CHECK(walked.load() < elements / 4);
    pairs += Index(everywhere.size());
  }
  CHECK(pairs > 100);
}

TEST_CASE("a continuous pass after the first finds the same pairs retesting only what the pass before moved") {
  // After one continuous pass on the crumpled sheets, a patch of the upper one plunging through the lower, every
  // pair still crossing has a particle of a pair that pass found (s.crossed): the full walk and the retest walk,
  // which keeps only such pairs and walks only elements whose swept box meets a cell of their reach grid, list the
  // same pairs, and the grid skips most elements. (Here the pairs left come from elements holding a moved particle,
  // so the reach's growth is not exercised: its cover is reach_grid_test's, its argument reach_of_a_particle's.)
  auto sc = two_sheets("continuous_retest");
  const Model& m = sc.built.model;
  std::mt19937 rng(23);
  Index pairs = 0;
  for (int trial = 0; trial < 4; ++trial) {
    State in = sc.built.state, out = in;
    crumple(m, rng, in, out, true);
    Workspace ws = make_workspace(m, sc.built.options);
    CollisionScratch& s = ws.collision;
    build_broad_phase(m, in, out, s);
    const std::int64_t first = collide_continuous(m, in, out, s, broad_mode(m.collision), sc.built.options.dt, false);
    build_cloth_broad_phase(m, in, out, s);
    find_crossings(m, in, out, s, broad_mode(m.collision), [](const Index*, int) { return true; });
    const auto everywhere = list_contacts(s);
    build_reach_grid(in, out, s.crossed, reach_of_a_particle(m, s), s.crossed_reach);
    std::atomic<Index> walked{0};
    auto near = [&](const Aabb& q) {
      if (!reaches(s.crossed_reach, q)) return false;
      walked.fetch_add(1);
      return true;
    };
    find_crossings(
        m, in, out, s, broad_mode(m.collision), [&](const Index* p, int count) { return crossed(s, p, count); },
        near);
    const Index elements = m.particle_count + Index(m.collision.edge_a.size());
    const Index marked = Index(std::count(s.crossed.begin(), s.crossed.end(), 1));
    INFO("trial " << trial << ": " << first << " responses in the first pass, " << marked << " particles moved, "
                  << everywhere.size() << " pairs left, " << walked.load() << " of " << elements
                  << " elements walked");
    CHECK(list_contacts(s) == everywhere);
    CHECK(walked.load() < elements / 3);
    pairs += Index(everywhere.size());
  }
  CHECK(pairs > 100);
}
