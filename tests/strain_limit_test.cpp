#include <doctest/doctest.h>

#include <cmath>

#include "spring_fixtures.h"
#include "systems/diagnostics.h"
#include "systems/spring_forces.h"
#include "systems/strain_limit.h"

using namespace clothsim;
using namespace clothsim::test;

namespace {

// A soft sheet hanging from its two top corners: without a limit its springs near the pins stretch far.
GridSpec soft_sheet(Real max_strain, Integrator integrator) {
  GridSpec g;
  g.nx = g.ny = 12;
  g.stiffness = 4;
  g.damping = 0.02;
  g.pins = {0, 11};
  g.max_strain = max_strain;
  g.integrator = integrator;
  return g;
}

// Largest strain seen after any step over `steps` steps of h.
Real worst_strain(const GridSpec& g, Real h, int steps, bool check_velocity = false) {
  BuiltScene s = grid_sheet(g);
  Workspace ws = make_workspace(s.model);
  State scratch = s.state;
  Real worst = 0;
  for (int k = 0; k < steps; ++k) {
    step(s.model, s.state, scratch, ws, h);
    if (check_velocity) {
      // The correction moved positions and velocities together: x' = x + h v' still holds.
      Real mismatch = 0;
      for (Index i = 0; i < s.model.particle_count; ++i)
        mismatch = std::max(mismatch, (scratch.x[i] - s.state.x[i] - h * scratch.v[i]).norm());
      REQUIRE(mismatch < 1e-12);
    }
    std::swap(s.state, scratch);
    REQUIRE(state_is_finite(s.state));
    worst = std::max(worst, max_spring_strain(s.model, s.state.x));
  }
  return worst;
}

}  // namespace

TEST_CASE("strain limiting keeps every spring within maxStrain + the documented tolerance") {
  const Real h = 1.0 / 240;
  const int steps = 480;  // two seconds
  const Real free_strain = worst_strain(soft_sheet(0, Integrator::implicit), h, steps);
  MESSAGE("largest strain without a limit " << free_strain);
  CHECK(free_strain > 0.3);
  for (Integrator integ : {Integrator::implicit, Integrator::symplectic}) {
    const Real limited = worst_strain(soft_sheet(0.1, integ), h, steps, true);
    MESSAGE("integrator " << int(integ) << ": largest strain with maxStrain 0.1: " << limited);
    CHECK(limited <= 0.1 + strain_limit_tolerance);
    CHECK(limited > 0.09);  // the limit is active, not a sheet that never stretched
  }
}

TEST_CASE("strain limit on one spring: a pinned end stays, the free end moves back to the limit") {
  BuiltScene s = two_particle_spring(0, 1, 10, 0, 1, 1.5, Integrator::symplectic);
  s.model.strain_limited = true;
  s.model.spring_max_strain = ParamField(0.2);
  Workspace ws = make_workspace(s.model);
  const int it = apply_strain_limit(s.model, s.state, ws, 0.1);
  CHECK(it == 1);  // one spring: a single Jacobi sweep is exact
  CHECK(s.state.x[0] == Vec3(0, 0, 0));
  CHECK(s.state.x[1].x() == doctest::Approx(1.2));
  CHECK(s.state.v[1].x() == doctest::Approx(-3.0));  // moved by -0.3 m over h = 0.1 s
  CHECK(max_spring_strain(s.model, s.state.x) == doctest::Approx(0.2));
}
