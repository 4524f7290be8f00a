#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "core/tethers.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;

namespace {

// A 3 x 3 grid of 1 m (spacing 0.5 m) with maxStrain 0.1, pinned where asked.
BuiltScene small_grid(std::vector<Index> pins, Real max_strain = 0.1) {
  SceneDesc scene = test::grid_scene(3, 3, 1.0, Integrator::symplectic);
  scene.cloths[0].max_strain = max_strain;
  scene.cloths[0].pins = std::move(pins);
  return test::build(scene);
}

Real tether_of(const Model& m, Index particle) {
  for (std::size_t t = 0; t < m.tether_particle.size(); ++t)
    if (m.tether_particle[t] == particle) return m.tether_length[t];
  return -1;
}

}  // namespace

TEST_CASE("tethers: a grid ties each free particle to its pin by the straight rest distance, a mesh by the springs") {
  BuiltScene b = small_grid({0});
  Model& m = b.model;
  CHECK(m.tether_particle.size() == 8);  // every particle but the pin
  // Particle 5 is (2, 1) in grid units from the pin at (0, 0): sqrt(1 + 0.25) m at rest.
  CHECK(tether_of(m, 5) == doctest::Approx(1.1 * std::sqrt(1.25)));
  CHECK(tether_of(m, 8) == doctest::Approx(1.1 * std::sqrt(2.0)));
  CHECK(tether_of(m, 0) == -1);
  // The same grid read as a mesh: the path over the springs, one structural (0.5) and one shear (0.5 sqrt 2),
  // longer than the straight line and never shorter than any path the limited springs allow.
  const std::vector<char> mesh_rest = {0};
  build_tethers(m, b.state.x, mesh_rest);
  CHECK(tether_of(m, 5) == doctest::Approx(1.1 * (0.5 + 0.5 * std::sqrt(2.0))));
  CHECK(tether_of(m, 8) == doctest::Approx(1.1 * std::sqrt(2.0)));  // the shear diagonal is straight
}

TEST_CASE("tethers: with two pins each particle goes to the nearer one, none without pins or without a limit") {
  const BuiltScene two = small_grid({0, 2});
  const Model& m = two.model;
  REQUIRE(m.tether_particle.size() == 7);
  for (std::size_t t = 0; t < m.tether_particle.size(); ++t) {
    const Index i = m.tether_particle[t], column = i % 3;
    if (column == 0) CHECK(m.tether_pin[t] == 0);
    if (column == 2) CHECK(m.tether_pin[t] == 2);
  }
  CHECK(tether_of(m, 1) == doctest::Approx(1.1 * 0.5));  // the middle of the pinned row: 0.5 m from either
  CHECK(small_grid({}).model.tether_particle.empty());
  CHECK(small_grid({0}, 0).model.tether_particle.empty());
}
