// The cloth-cloth response (Bridson, Fedkiw & Anderson 2002 §7.2): the inelastic stop and the spring-capped
// repulsion against their closed forms, the energy an overlapping pair gains against the spring it stands for,
// and stacked sheets that settle.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "systems/collision/collision_check.h"
#include "systems/collision/proximity.h"
#include "systems/collision/response.h"
#include "systems/diagnostics.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;

TEST_CASE("repulsion: an approach is stopped, then the pair gets the spring's impulse or a tenth of the overlap a step") {
  const Real h = 1e-3, overlap = 0.004, denom = 2000;  // two 1 g particles
  // Soft spring (k h^2 denom = 0.02 < 0.1): the spring's impulse h k overlap gives the change h k overlap denom.
  CHECK(repulsion_change(0, overlap, denom, 10, h) == doctest::Approx(1e-3 * 10 * 0.004 * 2000));  // 0.08 m/s
  // Stiff spring (k h^2 denom = 20): the change that closes a tenth of the overlap in a step, 0.1 overlap / h.
  CHECK(repulsion_change(0, overlap, denom, 1e7, h) == doctest::Approx(0.4));
  // Approaching at 3 m/s: stopped (3 m/s), then repelled from rest as above.
  CHECK(repulsion_change(-3, overlap, denom, 10, h) == doctest::Approx(3 + 0.08));
  // Already separating at 0.35 of the 0.4 m/s target: only the missing 0.05 m/s (below the spring's 0.08).
  CHECK(repulsion_change(0.35, overlap, denom, 10, h) == doctest::Approx(0.05));
  // Separating faster than the target: nothing.
  CHECK(repulsion_change(0.5, overlap, denom, 10, h) == 0);
}

namespace {

// A vertex (particle 0) over the centroid of a triangle (particles 1-3) in y = 0, all of mass `mass`, stretch
// stiffness k: its own Model, so the response is tested alone.
Model vertex_triangle_model(Real mass, Real k) {
  Model m;
  m.particle_count = 4;
  m.particle_inv_mass.assign(4, 1 / mass);
  m.particle_stiffness = ParamField(k);
  return m;
}

struct PairRun {
  Real energy = 0;  // kinetic energy once the pair is a thickness apart, J
  int steps = 0;    // steps until then
};

// Vertex over the triangle's centroid, `overlap` closer than the thickness, everything at rest; each step
// applies cloth_impulse (as the proximity pass does) and moves x += h v, until the vertex is a thickness away.
PairRun separate(const Model& m, Real thickness, Real overlap, Real h) {
  std::vector<Vec3> x = {Vec3(1.0 / 3, thickness - overlap, 1.0 / 3), Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0)};
  std::vector<Vec3> v(4, Vec3::Zero());
  const Index p[4] = {0, 1, 2, 3};
  const Real wt[4] = {1, -1.0 / 3, -1.0 / 3, -1.0 / 3};
  PairRun r;
  for (; r.steps < 100000; ++r.steps) {
    const Real d = x[0].y() - (x[1].y() + x[2].y() + x[3].y()) / 3;
    if (d >= thickness) break;
    Vec3 dv[4];
    if (cloth_impulse(p, wt, 4, m, v, Vec3(0, 1, 0), d, thickness, 0.3, h, dv))
      for (int k = 0; k < 4; ++k) v[k] += dv[k];
    for (int k = 0; k < 4; ++k) x[k] += h * v[k];
  }
  r.energy = kinetic_energy(m, v);
  return r;
}

}  // namespace

TEST_CASE("energy: a vertex-triangle pair brought into overlap at rest gains no more than the spring stores") {
  // 1 g particles, a soft cloth (k = 20 N/m), a 0.25 ms step, 1 cm thickness, 5 mm overlap. The pair's inverse
  // mass sum wt^2 / m = (1 + 3/9) / 1 g = 1333 /kg; k h^2 denom = 1.7e-3, well under 0.1: the spring caps every
  // step's impulse at h k overlap, so the repulsion is the spring k integrated by symplectic Euler, which from
  // rest releases at most its energy k overlap^2 / 2.
  const Real mass = 1e-3, k = 20, h = 2.5e-4, thickness = 0.01, overlap = 0.005;
  const Real denom = (1 + 3.0 / 9) / mass;
  const Real spring = 0.5 * k * overlap * overlap;  // 2.5e-4 J
  // The old response (0.1 overlap / h as a velocity, no cap) gave 0.5 (0.1 overlap / h)^2 / denom = 1.5e-3 J at
  // the first step: six times the spring's energy.
  const Real old_energy = 0.5 * std::pow(0.1 * overlap / h, 2) / denom;
  REQUIRE(old_energy > 5.9 * spring);
  const PairRun run = separate(vertex_triangle_model(mass, k), thickness, overlap, h);
  CHECK(run.energy <= spring);
  CHECK(run.energy > 0.8 * spring);  // the repulsion did act: most of the spring's energy came out
  MESSAGE("soft: energy gained " << run.energy << " J, spring " << spring << " J, old response " << old_energy
                                 << " J; a thickness apart after " << run.steps << " steps");
  // A stiff cloth (k = 2e5 N/m, k h^2 denom = 16.7): the tenth-of-the-overlap velocity caps. One kick from rest,
  // 0.1 overlap / h = 2 m/s, after which the pair separates faster than the shrinking overlap asks: its energy is
  // that kick's, 0.01 / (k h^2 denom) = 6e-4 of the spring's.
  const Real stiff = 2e5;
  const PairRun hard = separate(vertex_triangle_model(mass, stiff), thickness, overlap, h);
  CHECK(hard.energy == doctest::Approx(old_energy).epsilon(1e-9));
  CHECK(hard.energy <= 0.01 / (stiff * h * h * denom) * 0.5 * stiff * overlap * overlap * (1 + 1e-9));
  MESSAGE("stiff: energy gained " << hard.energy << " J, spring " << 0.5 * stiff * overlap * overlap << " J");
}

namespace {

// Figures of a run of a scene whose cloth 0 lies below cloth 1, frame by frame.
struct StackRun {
  std::vector<Real> kinetic;     // total kinetic energy, J
  std::vector<Real> top_gap;     // largest distance of an upper vertex from the lower sheet, m
  std::vector<Real> top_y;       // highest upper vertex, m
  std::vector<Real> speed;       // largest particle speed, m/s
  std::vector<Index> intersecting;  // intersecting triangle pairs (the --stats check)
  Real upper_mass = 0;           // kg
};

StackRun run_stack(const std::string& name, const std::string& xml) {
  const auto dir = test::scratch_dir("collision_response_" + name);
  test::write_text(dir / "s.xml", xml);
  auto sc = test::load_collision_scene(dir / "s.xml");
  StackRun r;
  const Model& model = sc.built.model;
  for (Index i = model.cloths[1].particle_begin; i < model.cloths[1].particle_end; ++i)
    r.upper_mass += 1 / model.particle_inv_mass[i];
  test::run_frames(sc, [&](int, const Model& m, const State& s, const Workspace&) {
    const ClothInfo& lower = m.cloths[0];
    const ClothInfo& upper = m.cloths[1];
    Real gap = 0, top = -1e300, speed = 0;
    for (Index i = upper.particle_begin; i < upper.particle_end; ++i) {
      Real best = 1e300;
      for (Index t = lower.tri_begin; t < lower.tri_end; ++t) {
        const Index* v = &m.tri_index[3 * t];
        best = std::min(best, point_triangle_distance(s.x[i], s.x[v[0]], s.x[v[1]], s.x[v[2]]));
      }
      gap = std::max(gap, best);
      top = std::max(top, s.x[i].y());
    }
    for (const Vec3& v : s.v) speed = std::max(speed, v.norm());
    r.kinetic.push_back(kinetic_energy(m, s.v));
    r.top_gap.push_back(gap);
    r.top_y.push_back(top);
    r.speed.push_back(speed);
    r.intersecting.push_back(count_intersecting_triangles(m, s.x));
  });
  return r;
}

// A 1 m sheet (16 x 16) lying on the ground plane and a 0.5 m sheet (10 x 10) dropped flat onto it from `drop`
// above its resting height (ground + two thicknesses); both 1 cm thick, 0.2 kg/m^2, k = 200 N/m, no air damping.
constexpr Real stack_thickness = 0.01, stack_drop = 0.05;
std::string stack_scene(Real timestep, int end_frame) {
  char xml[2048];
  std::snprintf(xml, sizeof xml, R"(<scene>
  <simulation timestep="%g" fps="24" startFrame="1" endFrame="%d" collisionIterations="2"/>
  <plane name="ground" point="0 0 0" normal="0 1 0"/>
  <cloth name="lower" grid="16 16" size="1 1" translate="0 %g 0">
    <density value="0.2"/><stiffness value="200"/><thickness value="%g"/>
  </cloth>
  <cloth name="upper" grid="10 10" size="0.5 0.5" translate="0.013 %g -0.021">
    <density value="0.2"/><stiffness value="200"/><thickness value="%g"/>
  </cloth></scene>)",
                timestep, end_frame, stack_thickness, stack_thickness, 2 * stack_thickness + stack_drop,
                stack_thickness);
  return xml;
}

}  // namespace

TEST_CASE("stacked sheets settle: a sheet dropped on a sheet lying on the ground comes to rest on it" * doctest::test_suite("slow")) {
  // 2 s at a 0.25 ms step. The drop's potential energy m g 5 cm (m = 0.05 kg: 0.2 kg/m^2 over 0.25 m^2) is
  // 0.0245 J.
  const StackRun r = run_stack("settle", stack_scene(0.00025, 49));
  const Real drop_energy = r.upper_mass * 9.81 * stack_drop;
  REQUIRE(r.upper_mass == doctest::Approx(0.05));
  Index intersecting = 0;
  for (Index n : r.intersecting) intersecting += n;
  CHECK(intersecting == 0);
  // After 2 s everything is at rest: the kinetic energy below 1% of what the drop released.
  CHECK(r.kinetic.back() < 0.01 * drop_energy);
  // From 1 s on the upper sheet lies on the lower: no vertex more than three thicknesses from it; and none
  // ever rises a thickness above where it was dropped from (the contact does not throw it back up).
  Real gap = 0;
  for (std::size_t f = 24; f < r.top_gap.size(); ++f) gap = std::max(gap, r.top_gap[f]);
  CHECK(gap < 3 * stack_thickness);
  CHECK(*std::max_element(r.top_y.begin(), r.top_y.end()) < 3 * stack_thickness + stack_drop);
  MESSAGE("kinetic energy at 2 s " << r.kinetic.back() << " J of the drop's " << drop_energy
                                   << " J; largest gap from 1 s on " << gap << " m; largest speed "
                                   << *std::max_element(r.speed.begin(), r.speed.end()) << " m/s");
}
