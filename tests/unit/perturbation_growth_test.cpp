// The growth detector of the stability study against explicit Euler on one damped oscillator, whose growth per
// step is known in closed form (docs/stability.md, "The automatic step against the largest stable step").
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "systems/perturbation_growth.h"
#include "systems/stability.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;
using namespace clothsim::test;

TEST_CASE("perturbation growth on a damped oscillator: explicit Euler's closed form either side of its limit") {
  // One free 0.01 kg mass on k = 400 N/m, kd = 0.2 N s/m along x: w = 200 rad/s, g = 20 1/s, a light damping
  // (g/w = 0.1). Explicit Euler's step matrix [[1, h], [-h w^2, 1 - h g]] has determinant 1 - h g + h^2 w^2,
  // the squared modulus of its complex eigenvalues: rho^2 = 1 - h g + h^2 w^2, stable for h <= g / w^2 = 0.5 ms.
  const Real w = 200, g = 20, limit = g / (w * w);
  const int windows = 6;
  for (const Real r : {0.95, 1.05}) {
    CAPTURE(r);
    const BuiltScene s = two_particle_spring(400, 0.2, 0.01, 1, 1e-4, Integrator::euler);
    const Real h = r * limit;
    const std::int64_t steps = std::llround(12 / h);  // 12 s: the amplitude changes by e^(+-6)
    const std::vector<Real> growth = perturbation_growth(s.model, s.options, s.state, h, steps, windows);
    REQUIRE(growth.size() == std::size_t(windows));
    // ln of the growth over a window of steps / windows steps: +-1.0 (g (r - 1) / 2 per second, 2 s a window).
    const Real per_window = Real(steps / windows) * 0.5 * std::log(1 - h * g + h * h * w * w);
    CHECK(std::abs(per_window) == doctest::Approx(1.0).epsilon(0.01));
    if (r < 1) {
      // The deviation along the spring decays; the first window shows the rate before the twin's sideways offset
      // (a neutral pendulum motion about the pin, which the deviation barely sees) is all that is left.
      CHECK(growth[0] == doctest::Approx(per_window).epsilon(0.05));
      CHECK(!grows_exponentially(growth));
    } else {
      for (const Real gw : growth) CHECK(gw == doctest::Approx(per_window).epsilon(0.05));
      CHECK(grows_exponentially(growth));
      // The run's own divergence check does not see it: the amplitude grew e^6 from 1e-4 m, 0.3 J against 20 J.
      State start = s.state;
      CHECK(!run_diverges(s.model, s.options, start, h, steps));
    }
  }
}

TEST_CASE("grows_exponentially needs every window of the second half to grow and a total past the factor") {
  CHECK(grows_exponentially(std::vector<Real>{-3, 5, 0.8, 0.8, 0.8, 0.8}, 10));     // 2.4 > ln 10
  CHECK(!grows_exponentially(std::vector<Real>{-3, 5, 0.7, 0.7, 0.7, 0.7}, 10));    // 2.1 < ln 10
  CHECK(!grows_exponentially(std::vector<Real>{0, 0, 0, 3.0, -0.1, 3.0}, 10));      // a burst undone
  CHECK(grows_exponentially(std::vector<Real>{0, 0.1, INFINITY}, 10));              // a state not finite
  CHECK(!grows_exponentially(std::vector<Real>{}, 10));
}
