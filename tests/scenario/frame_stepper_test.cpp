// The frame's steps (sim/frame_stepper.h): with timestep="auto", the chosen step, rejection that keeps the state,
// halving and growing back, determinism; with a fixed step, the implicit step's checks reported.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "io/scene_family.h"
#include "sim/frame_stepper.h"
#include "systems/auto_step.h"
#include "systems/diagnostics.h"
#include "systems/spring_forces.h"
#include "systems/strain_limit.h"
#include "systems/step.h"
#include "tests/support/collision_scene.h"
#include "tests/support/scene_fixtures.h"
#include "tests/support/thread_bytes.h"

using namespace clothsim;
using namespace clothsim::test;
using clothsim::sim::FrameStepper;
using clothsim::sim::FrameSteps;
using clothsim::sim::StepVerdict;

namespace {

BuiltScene load_auto(const std::string& name, const std::string& xml) { return load_scene_text(name, xml).built; }

// `frames` frames of the stepper from the scene's start, the reports summed; returns whether they finished.
bool run_frames(const BuiltScene& b, State& state, FrameSteps& total, int frames = 1) {
  State scratch = state;
  Workspace ws = make_workspace(b.model, b.options);
  FrameStepper stepper(b.model, b.options, b.state);
  for (int f = 0; f < frames; ++f) {
    FrameSteps r;
    const bool ok = stepper.advance_frame(b.model, b.options, state, scratch, ws, r);
    total.smallest = f == 0 ? r.smallest : std::min(total.smallest, r.smallest);
    total.largest = std::max(total.largest, r.largest);
    total.taken += r.taken;
    total.rejected += r.rejected;
    if (!ok) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("auto picks the largest step that divides the frame and stays within stepSafety x the limit") {
  const BuiltScene b = load_auto("auto_pick", io::family_scene(3, "auto").xml);
  const SimOptions& m = b.options;
  const Real target = auto_step_target(m, stable_steps(estimate_modes(b.model, b.state.x)));
  CHECK(m.auto_step);
  CHECK(m.dt <= target);
  CHECK(1 / (m.fps * (m.steps_per_frame - 1)) > target);  // one step fewer a frame would exceed it
  CHECK(m.dt * m.steps_per_frame * m.fps == doctest::Approx(1));
  CHECK(m.min_dt == doctest::Approx(m.dt / 1024));
}

TEST_CASE("a failing step is rejected with the state untouched and below minTimestep the frame stops") {
  // Implicit with one CG iteration against a 1e-12 tolerance: every solve stops at its cap, so every step fails,
  // halves, and after 10 halvings (minTimestep = dt / 1024) the stepper gives up.
  // A pinned scene of the family (a free one falls with a uniform velocity change, which one CG step solves).
  int seed = 0;
  while (io::family_scene(seed).xml.find("<pins") == std::string::npos) ++seed;
  std::string xml = io::family_scene(seed, "auto").xml;
  const auto at = xml.find("integrator=\"");
  xml.replace(at, xml.find('"', at + 12) - at + 1, "integrator=\"implicit\" preconditioner=\"jacobi\" cgMaxIterations=\"1\" cgTolerance=\"1e-12\"");
  const BuiltScene b = load_auto("auto_fail", xml);
  State state = b.state;
  FrameSteps report;
  CHECK_FALSE(run_frames(b, state, report));
  CHECK(report.taken == 0);
  CHECK(report.rejected == 11);  // dt, dt/2, ..., dt/1024: halving that last one would go below minTimestep
  CHECK(same_bytes(state.x, b.state.x));
  CHECK(same_bytes(state.v, b.state.v));
  CHECK(state.step == 0);
}

TEST_CASE("too large a step is halved until stable and grows back with the same steps and bytes at 1 and 2 threads") {
  // Scene 7 at 8x its automatic step: past the limit, so strain jumps and the stepper halves.
  BuiltScene b = load_auto("auto_grow", io::family_scene(7, "auto").xml);
  const Real chosen = b.options.dt;
  b.options.dt *= 8;
  b.options.steps_per_frame = std::max(1, b.options.steps_per_frame / 8);
  b.options.dt = 1 / (b.options.fps * b.options.steps_per_frame);
  io::perturb_start(b.model, b.state, 1e-4);
  State one = b.state, two = b.state;
  FrameSteps r1, r2;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    REQUIRE(run_frames(b, one, r1, 10));
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    REQUIRE(run_frames(b, two, r2, 10));
  }
  CAPTURE(chosen);
  CHECK(r1.rejected >= 1);
  CHECK(r1.smallest < b.options.dt);
  CHECK(r1.smallest <= 1.001 * chosen * 2);  // it had to come down near the stable step
  CHECK(r1.largest > r1.smallest);
  CHECK(state_is_finite(one));
  CHECK(one.time == doctest::Approx(10 / b.options.fps));
  CHECK(r1.taken == r2.taken);
  CHECK(r1.rejected == r2.rejected);
  CHECK(same_bytes(one.x, two.x));
  CHECK(same_bytes(one.v, two.v));
}

// A horizontal spring at rest, pinned at the origin, its free end under gravity: the linearisation about rest has
// no transverse stiffness (k (1 - rest/l) = 0), so one backward-Euler step drops the end by g h^2 whatever k is,
// and leaves the spring stretched by sqrt(1 + (g h^2 / rest)^2) - 1.
TEST_CASE("a fixed implicit step that stretches a spring by more than strain_jump is kept and reported with its strain") {
  for (const Real h : {0.1, 0.01}) {
    CAPTURE(h);
    BuiltScene b = two_particle_spring(1e6, 0, 0.01, 0.1, 0, Integrator::implicit);
    b.model.gravity = Vec3(0, -9.81, 0);
    b.options.dt = h;
    b.options.steps_per_frame = 1;
    State state = b.state, scratch = b.state;
    Workspace ws = make_workspace(b.model, b.options);
    FrameStepper stepper(b.model, b.options, b.state);
    FrameSteps r;
    REQUIRE(stepper.advance_frame(b.model, b.options, state, scratch, ws, r));
    const Real expected = std::sqrt(1 + std::pow(9.81 * h * h / 0.1, 2)) - 1;  // 0.4007 and 4.8e-5
    CHECK(r.taken == 1);
    CHECK(r.rejected == 0);
    CHECK(state.step == 1);  // kept: a fixed step is reported, not retried
    if (h == 0.1) {
      REQUIRE(r.failed == 1);
      CHECK(r.first_failure.verdict == StepVerdict::strain_jump);
      CHECK(r.first_failure.strain_before == doctest::Approx(0).epsilon(1e-12));
      CHECK(r.first_failure.strain_after == doctest::Approx(expected).epsilon(1e-9));
      CHECK(r.first_failure.solve.converged);
    } else {
      CHECK(r.failed == 0);
      CHECK(max_spring_strain(b.model, state.x) == doctest::Approx(expected).epsilon(1e-6));
    }
  }
}
