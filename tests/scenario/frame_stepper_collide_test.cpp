// The automatic step's rules for the collide stage (sim/frame_stepper.h, docs/stability.md "Automatic steps"):
// strain jumps the collide stage makes against still and moving colliders, the floor-step probe, the cloth's own
// travel, and impact zones left unresolved while a collider moves.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "sim/frame_stepper.h"
#include "systems/collision/collision_check.h"
#include "systems/diagnostics.h"
#include "systems/spring_forces.h"
#include "systems/step.h"
#include "systems/strain_limit.h"
#include "tests/support/collision_scene.h"
#include "tests/support/scene_fixtures.h"
#include "tests/support/thread_bytes.h"

using namespace clothsim;
using namespace clothsim::sim;  // FrameStepper, FrameSteps, StepVerdict, LoadedScene
using namespace clothsim::test;

namespace {

// A 3 x 3 sheet (10 cm springs) at rest without gravity, 4 cm thick, pierced by a vertical needle (a thin collider
// triangle) through the centroid of one of its triangles, 2.9 cm from its edges: the collide stage pushes those
// edges out to one thickness from the needle, a push that does not depend on the step.
// With `moving`, the needle is a two-frame sequence that moves 2 cm along x over the frame, from `from` m along x.
std::string needle_scene(const std::string& name, const std::string& timestep, bool moving = false, Real from = 0) {
  const auto dir = scratch_dir(name);
  auto needle = [](Real dx) {
    char text[160];
    std::snprintf(text, sizeof text, "v %.4f -1 -0.0667\nv %.4f -1 -0.0667\nv %.4f 1 -0.0667\nf 1 2 3\n", -0.0672 + dx,
                  -0.0662 + dx, -0.0667 + dx);
    return std::string(text);
  };
  write_text(dir / "needle.obj", needle(0));
  write_text(dir / "needle1.obj", needle(from));
  write_text(dir / "needle2.obj", needle(from + 0.02));
  const std::string collider = moving ? "sequence=\"" + (dir / "needle#.obj").string() : "obj=\"" + (dir / "needle.obj").string();
  return R"(<scene>
  <simulation timestep=")" + timestep + R"(" fps="100" startFrame="1" endFrame="2" integrator="implicit" gravity="0 0 0"/>
  <cloth name="sheet" grid="3 3" size="0.2 0.2"><thickness value="0.04"/></cloth>
  <static )" + collider + R"("/>
</scene>)";
}

}  // namespace

TEST_CASE("auto: a strain jump of the collide stage against a still collider is kept and reported") {
  const BuiltScene b = load_scene_text("auto_geometric", needle_scene("auto_geometric_mesh", "auto")).built;
  State state = b.state;
  State scratch = state;
  Workspace ws = make_workspace(b.model, b.options);
  FrameStepper stepper(b.model, b.options, b.state);
  FrameSteps r;
  REQUIRE(stepper.advance_frame(b.model, b.options, state, scratch, ws, r));
  CHECK(state.time == doctest::Approx(0.01));
  CHECK(r.rejected == 0);  // a smaller step would push as far: kept at once
  REQUIRE(r.failed == 1);
  CHECK(r.first_failure.verdict == StepVerdict::strain_jump);
  CHECK(r.first_failure.step == doctest::Approx(b.options.dt));
  CHECK(r.first_failure.strain_before == doctest::Approx(0).epsilon(1e-12));
  CHECK(r.first_failure.strain_after > 0.1);
  // The same push from one fixed step: the auto step kept exactly what a fixed one does.
  const BuiltScene f = load_scene_text("auto_geometric_fixed", needle_scene("auto_geometric_fixed_mesh", "0.01")).built;
  State fixed = f.state, fixed_scratch = f.state;
  Workspace fws = make_workspace(f.model, f.options);
  FrameStepper fixed_stepper(f.model, f.options, f.state);
  FrameSteps fr;
  REQUIRE(fixed_stepper.advance_frame(f.model, f.options, fixed, fixed_scratch, fws, fr));
  REQUIRE(fr.failed == 1);
  MESSAGE("strain after the push: " << r.first_failure.strain_after << " (auto), " << fr.first_failure.strain_after
                                    << " (fixed)");
  CHECK(r.first_failure.strain_after == fr.first_failure.strain_after);
}

// A 3 x 3 sheet pinned round its border (10 cm springs, 4 cm thick, no gravity) and a small horizontal plate under
// its free centre vertex that rises 7 cm in the 10 ms frame, from 5 cm below the sheet to 2 cm above it: the
// collide stage lifts the centre to one thickness above the plate, 6 cm, a push that falls with the step.
std::string plate_scene(const std::string& name) {
  const auto dir = scratch_dir(name);
  auto plate = [](Real y) {
    char text[160];
    std::snprintf(text, sizeof text, "v -0.02 %.4f -0.02\nv -0.02 %.4f 0.03\nv 0.03 %.4f -0.02\nf 1 2 3\n", y, y, y);
    return std::string(text);
  };
  write_text(dir / "plate1.obj", plate(-0.05));
  write_text(dir / "plate2.obj", plate(0.02));
  return R"(<scene>
  <simulation timestep="auto" fps="100" startFrame="1" endFrame="2" integrator="implicit" gravity="0 0 0"/>
  <cloth name="sheet" grid="3 3" size="0.2 0.2"><thickness value="0.04"/><pins vertices="0 1 2 3 5 6 7 8"/></cloth>
  <static sequence=")" + (dir / "plate#.obj").string() + R"("/>
</scene>)";
}

TEST_CASE("auto: a strain jump while a collider moves into the cloth by more than a quarter thickness is halved") {
  // The whole step lifts the centre 6 cm (strain 0.166 on its four springs); the probe at minTimestep lifts it
  // nothing, so the jump comes from the plate's motion and the step is halved.
  const auto sc = load_scene_text("auto_moving", plate_scene("auto_moving_mesh"));
  const Real dt = sc.built.options.dt;
  int frames = 0;
  run_frames(sc, [&](int f, const Model&, const State& state, const Workspace&, const sim::FrameReport& r) {
    if (f == sc.built.options.start_frame) return;
    ++frames;
    CHECK(state.time == doctest::Approx(0.01));
    CHECK(r.steps.rejected >= 2);  // the whole step and its probe at least
    CHECK(r.steps.smallest <= dt / 2);
    // The plate hits the centre at 7 m/s and throws it up: later steps may still jump and be kept, but only at
    // a halved step (without the probe's test the whole step was kept).
    if (r.steps.failed > 0) CHECK(r.steps.first_failure.step <= dt / 2);
    MESSAGE("rejected " << r.steps.rejected << ", steps " << r.steps.taken << ", smallest step " << r.steps.smallest);
  });
  CHECK(frames == 1);
}

// Runs the scene's one 10 ms frame and checks that its single step was kept with a collide-stage strain jump (the
// strain before it 0, as in the needle scenes) after `rejected` rejected steps, probes included.
void check_kept_whole_step(const sim::LoadedScene& sc, int rejected) {
  int frames = 0;
  run_frames(sc, [&](int f, const Model&, const State& state, const Workspace&, const sim::FrameReport& r) {
    if (f == sc.built.options.start_frame) return;
    ++frames;
    CHECK(state.time == doctest::Approx(0.01));
    CHECK(r.steps.rejected == rejected);
    CHECK(r.steps.taken == 1);
    REQUIRE(r.steps.failed == 1);
    CHECK(r.steps.first_failure.verdict == StepVerdict::strain_jump);
    CHECK(r.steps.first_failure.step == doctest::Approx(0.01));
    CHECK(r.steps.first_failure.strain_before == doctest::Approx(0).epsilon(1e-12));
    CHECK(r.steps.first_failure.strain_after > FrameStepper::strain_jump);
  });
  CHECK(frames == 1);
}

TEST_CASE("auto: a collide-stage jump that a step at minTimestep still makes is kept as that step") {
  // The needle through the sheet moving 2 cm in the frame: its probe at minTimestep (10 ms / 1024) still pushes the
  // sheet's edges out to the thickness (the pierce, not the motion), so the probe's step is kept and reported in
  // place of the 10 ms step, and the steps grow back over the rest of the frame.
  const auto sc = load_scene_text("auto_moving_pierced", needle_scene("auto_moving_pierced_mesh", "auto", true));
  const Real dt = sc.built.options.dt, floor_step = std::ldexp(dt, -10);
  int frames = 0;
  run_frames(sc, [&](int f, const Model&, const State& state, const Workspace&, const sim::FrameReport& r) {
    if (f == sc.built.options.start_frame) return;
    ++frames;
    CHECK(state.time == doctest::Approx(0.01));
    CHECK(r.steps.rejected == 1);  // the 10 ms step, replaced by its probe
    REQUIRE(r.steps.failed >= 1);
    CHECK(r.steps.first_failure.verdict == StepVerdict::strain_jump);
    CHECK(r.steps.first_failure.step == floor_step);
    CHECK(r.steps.first_failure.strain_before == doctest::Approx(0).epsilon(1e-12));
    CHECK(r.steps.first_failure.strain_after > FrameStepper::strain_jump);
    CHECK(r.steps.smallest == floor_step);
    CHECK(r.steps.largest == dt / 2);  // grown back, one level at each aligned point, to the frame's last half
    MESSAGE("steps " << r.steps.taken << ", kept " << r.steps.failed);
  });
  CHECK(frames == 1);
  // The probe's steps and bytes are the same at 1 and 2 threads.
  std::vector<Vec3> x[2];
  int rejected[2] = {0, 0};
  for (int t = 0; t < 2; ++t) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, t + 1);
    run_frames(sc, [&](int f, const Model&, const State& state, const Workspace&, const sim::FrameReport& r) {
      if (f == sc.built.options.start_frame) return;
      x[t] = state.x;
      rejected[t] = r.steps.rejected;
    });
  }
  CHECK(rejected[0] == 1);
  CHECK(rejected[1] == 1);
  CHECK(same_bytes(x[0], x[1]));
}

TEST_CASE("auto: the strain limit's corrections in a pierced sheet do not count as the cloth's travel") {
  // The needle's sheet as an OBJ whose rest mesh is 0.8 times its size, with maxStrain 0.1: every spring starts 25%
  // long, and the strain limit moves a particle by 2.1 cm in the first step, more than a quarter of
  // the 4 cm thickness, whatever the step. The cloth's own motion (h |v| from the integrator) is far smaller,
  // so the step is kept whole, as against the plain sheet.
  const auto dir = scratch_dir("auto_limit_travel_sheet");
  auto grid = [](Real s) {
    std::string text;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        text += "v " + std::to_string(s * 0.1 * (i - 1)) + " 0 " + std::to_string(s * 0.1 * (j - 1)) + "\n";
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int a = 1 + i + 3 * j, b = a + 1, c = a + 3, d = c + 1;
        text += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(b) + "\nf " +
                std::to_string(b) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
      }
    return text;
  };
  write_text(dir / "sheet.obj", grid(1));
  write_text(dir / "rest.obj", grid(0.8));
  std::string xml = needle_scene("auto_limit_travel_mesh", "auto");
  const std::string from = R"(<cloth name="sheet" grid="3 3" size="0.2 0.2">)";
  xml.replace(xml.find(from), from.size(),
              "<cloth name=\"sheet\" obj=\"" + (dir / "sheet.obj").string() + "\" rest=\"" + (dir / "rest.obj").string() +
                  "\" maxStrain=\"0.1\"><stiffness value=\"1\"/>");
  // Without the needle, one step of the sheet: the strain limit alone moves a particle by more than a quarter
  // thickness (the figure the old rule counted as travel).
  std::string alone = xml;
  alone.erase(alone.find("<static"), alone.find("</scene>") - alone.find("<static"));
  const BuiltScene a = load_scene_text("auto_limit_travel_alone", alone).built;
  State a1 = a.state;
  Workspace aws = make_workspace(a.model, a.options);
  step(a.model, a.options, a.state, a1, aws, a.options.dt);
  Real limited = 0;
  for (Index i = 0; i < a.model.particle_count; ++i) limited = std::max(limited, (a1.x[i] - a.state.x[i]).norm());
  const Real quarter = FrameStepper::travel_fraction * 0.04;
  CHECK(limited > quarter);

  const BuiltScene b = load_scene_text("auto_limit_travel", xml).built;
  State state = b.state, scratch = state;
  Workspace ws = make_workspace(b.model, b.options);
  const StepResult one = step(b.model, b.options, state, scratch, ws, b.options.dt);
  MESSAGE("moved by the strain limit " << limited << " m, travel " << one.travel << " m, strain before collide "
                                       << one.strain_before_collide << ", after " << max_spring_strain(b.model, scratch.x));
  CHECK(one.travel < quarter);
  CHECK(one.strain_before_collide == doctest::Approx(0.1).epsilon(0.01));
  FrameStepper stepper(b.model, b.options, b.state);
  FrameSteps r;
  state = b.state;
  ws = make_workspace(b.model, b.options);
  REQUIRE(stepper.advance_frame(b.model, b.options, state, scratch, ws, r));
  // The whole step is kept, not halved for travel the cloth did not make. The needle's push no longer fails it:
  // the strain limit after the collide stage pulls the pushed particle's neighbours after it (before that pass,
  // this step was kept and reported with the strain jumping past 0.1).
  CHECK(r.rejected == 0);
  CHECK(r.taken == 1);
  CHECK(r.failed == 0);
  CHECK(max_spring_strain(b.model, state.x) <= 0.1 + strain_limit_tolerance);
}

TEST_CASE("auto: a collide-stage jump that moving colliders still make at minTimestep is kept, not a stop") {
  // The moving needle of the test above with minTimestep 6 ms: the 10 ms step may not halve, and its jump is the
  // collide stage's (the strain before it stays 0), so it is kept and reported at 10 ms where the run used to stop.
  std::string xml = needle_scene("auto_floor_mesh", "auto", true);
  const std::string from = R"(timestep="auto")";
  xml.replace(xml.find(from), from.size(), R"(timestep="auto" minTimestep="0.006")");
  check_kept_whole_step(load_scene_text("auto_floor", xml), 0);
}

namespace {

// Two equal sheets 1 cm apart (4 mm thick, no gravity) thrown at each other at 2 m/s each, every vertex's velocity
// jittered by up to 0.3 m/s (seeded), with one continuous pass and one impact zone pass a step, under a plate
// that comes down `drop` m in the frame towards the upper sheet (a two-frame OBJ sequence, 1 cm over it at first).
sim::LoadedScene thrown_sheets(const std::string& name, const std::string& timestep, Real drop) {
  const auto dir = scratch_dir(name);
  auto plate = [](Real y) {  // facing down, the cloth's side
    char text[200];
    std::snprintf(text, sizeof text, "v -0.3 %.4f -0.3\nv -0.3 %.4f 0.3\nv 0.3 %.4f 0.3\nv 0.3 %.4f -0.3\nf 1 3 2\nf 1 4 3\n",
                  y, y, y, y);
    return std::string(text);
  };
  write_text(dir / "plate1.obj", plate(0.02));
  write_text(dir / "plate2.obj", plate(0.02 - drop));
  write_text(dir / "scene.xml", R"(<scene>
  <simulation timestep=")" + timestep + R"(" fps="100" startFrame="1" endFrame="2" integrator="implicit"
              gravity="0 0 0" collisionIterations="1" impactZoneIterations="1"/>
  <cloth name="a" grid="6 6" size="0.2 0.2"><thickness value="0.004"/></cloth>
  <cloth name="b" grid="7 7" size="0.2 0.2" translate="0.011 0.01 0.007"><thickness value="0.004"/></cloth>
  <static sequence=")" + (dir / "plate#.obj").string() + R"("/>
</scene>)");
  sim::LoadedScene sc = load_collision_scene(dir / "scene.xml");
  std::mt19937 rng(3);
  std::uniform_real_distribution<Real> u(-0.3, 0.3);
  for (int k = 0; k < 2; ++k)
    for (Index i = sc.built.model.cloths[k].particle_begin; i < sc.built.model.cloths[k].particle_end; ++i)
      sc.built.state.v[i] = Vec3(u(rng), (k == 0 ? 2 : -2) + u(rng), u(rng));
  return sc;
}

// The sheets' mean heights.
Real mean_y(const Model& m, std::span<const Vec3> x, int k) {
  Real y = 0;
  for (Index i = m.cloths[k].particle_begin; i < m.cloths[k].particle_end; ++i) y += x[i].y();
  return y / Real(m.cloths[k].particle_end - m.cloths[k].particle_begin);
}

struct ThrownEnd {
  State state;
  sim::FrameReport report;
};

ThrownEnd run_thrown(const sim::LoadedScene& sc) {
  ThrownEnd end;
  test::run_frames(sc, [&](int f, const Model&, const State& state, const Workspace&, const sim::FrameReport& r) {
    if (f == sc.built.options.start_frame) return;
    end.state = state;
    end.report = r;
  });
  return end;
}

}  // namespace

TEST_CASE("auto: a step whose impact zones stop unresolved while a collider moves is halved") {
  // The sheets meet after 1.5 ms (6 mm closed at 4 m/s) near y = 5 mm and stop each other; the plate, 3 cm down in
  // the frame, reaches them at 3 ms and carries them down with it, so they end one thickness under it and one
  // under each other: y = -14 and -18 mm, 4 mm apart. One fixed 10 ms step leaves its zone unresolved, and the
  // zone, holding plate vertices, takes the plate's motion whole: both sheets move 3 cm down rigidly, still 1 cm
  // apart, as if they had never met.
  const sim::LoadedScene fixed_scene = thrown_sheets("auto_zones_fixed", "0.01", 0.03);
  const sim::LoadedScene auto_scene = thrown_sheets("auto_zones", "auto", 0.03);
  const Model& m = auto_scene.built.model;
  const ThrownEnd fixed = run_thrown(fixed_scene), autos = run_thrown(auto_scene);
  const Real plate_end = -0.01, thickness = 0.004;
  auto gap = [&](const State& s) { return mean_y(m, s.x, 1) - mean_y(m, s.x, 0); };
  MESSAGE("mean heights of the sheets (lower, upper): fixed " << mean_y(m, fixed.state.x, 0) << ", "
          << mean_y(m, fixed.state.x, 1) << " m; auto " << mean_y(m, autos.state.x, 0) << ", "
          << mean_y(m, autos.state.x, 1) << " m in " << autos.report.steps.taken << " steps, "
          << autos.report.steps.rejected << " rejected, the smallest " << autos.report.steps.smallest << " s");
  CHECK(auto_scene.built.options.dt == 0.01);
  CHECK(fixed.report.steps.counts.zones.unresolved == 1);
  CHECK(gap(fixed.state) > 2 * thickness);
  CHECK(count_intersecting_triangles(m, fixed.state.x) == 0);
  // The automatic step rejects that step for its zones and halves it: the sheets meet, under the plate.
  CHECK(autos.report.steps.rejected >= 1);
  CHECK(autos.report.steps.last_rejection == StepVerdict::zones_unresolved);
  CHECK(autos.report.steps.smallest < 0.01);
  CHECK(gap(autos.state) > 0);
  CHECK(gap(autos.state) < thickness);
  CHECK(mean_y(m, autos.state.x, 1) < plate_end);
  CHECK(count_intersecting_triangles(m, autos.state.x) == 0);
}

TEST_CASE("auto: impact zones left unresolved against a still collider are kept as a fixed step keeps them") {
  // The same sheets under a plate that does not move: a smaller step would not split any collider's motion.
  const sim::LoadedScene fixed_scene = thrown_sheets("auto_zones_still_fixed", "0.01", 0);
  const sim::LoadedScene auto_scene = thrown_sheets("auto_zones_still", "auto", 0);
  const ThrownEnd fixed = run_thrown(fixed_scene), autos = run_thrown(auto_scene);
  CHECK(fixed.report.steps.counts.zones.unresolved == 1);
  CHECK(autos.report.steps.counts.zones.unresolved == 1);
  CHECK(autos.report.steps.rejected == 0);
  CHECK(autos.report.steps.taken == 1);
  CHECK(same_bytes(autos.state.x, fixed.state.x));
}
