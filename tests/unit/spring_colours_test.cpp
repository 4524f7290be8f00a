#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

#include "core/spring_colours.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;

namespace {

// Every limited spring once, no particle twice within a colour, and springs of a colour in index order.
void check_schedule(const Model& m) {
  std::vector<int> seen(m.spring_count, 0);
  std::vector<Index> last_colour(m.particle_count, -1);
  const Index colours = Index(m.spring_colour_offset.size()) - 1;
  for (Index c = 0; c < colours; ++c) {
    CHECK(m.spring_colour_offset[c] < m.spring_colour_offset[c + 1]);  // no empty colour
    for (Index k = m.spring_colour_offset[c]; k < m.spring_colour_offset[c + 1]; ++k) {
      const Index s = m.spring_colour_spring[k];
      ++seen[s];
      if (k > m.spring_colour_offset[c]) CHECK(m.spring_colour_spring[k - 1] < s);
      for (Index i : {m.spring_a[s], m.spring_b[s]}) {
        CHECK(last_colour[i] != c);
        last_colour[i] = c;
      }
    }
  }
  for (Index s = 0; s < m.spring_count; ++s) CHECK(seen[s] == (spring_is_limited(m, s) ? 1 : 0));
}

}  // namespace

TEST_CASE("spring colours: a limited grid's springs in 13 colours, each once, no particle twice in a colour") {
  SceneDesc scene = test::grid_scene(16, 16, 1.0, Integrator::symplectic);
  scene.cloths[0].max_strain = 0.1;
  const BuiltScene b = test::build(scene);
  const Model& m = b.model;
  // An interior particle has 12 springs (4 structural, 4 shear, 4 flex), so 12 colours at least; the greedy
  // order takes one more.
  CHECK(m.spring_colour_offset.size() == 14);
  CHECK(m.spring_colour_spring.size() == std::size_t(m.spring_count));
  check_schedule(m);
}

TEST_CASE("spring colours: springs between two pins and springs of unlimited cloths are left out") {
  SceneDesc scene = test::grid_scene(4, 4, 1.0, Integrator::symplectic);
  scene.cloths[0].max_strain = 0.1;
  scene.cloths[0].pins = {0, 1, 2, 3};  // the first row: 3 structural and 2 flex springs join two pins
  ClothDesc free_cloth = scene.cloths[0];
  free_cloth.name = "free";
  free_cloth.max_strain = 0;  // no limit: none of its springs is projected
  free_cloth.pins.clear();
  scene.cloths.push_back(free_cloth);
  const BuiltScene b = test::build(scene);
  const Model& m = b.model;
  REQUIRE(m.cloths.size() == 2);
  const Index per_cloth = m.cloths[0].spring_end - m.cloths[0].spring_begin;
  CHECK(m.spring_colour_spring.size() == std::size_t(per_cloth - 5));
  check_schedule(m);
  // A model without a limit keeps no schedule.
  scene.cloths[0].max_strain = 0;
  CHECK(test::build(scene).model.spring_colour_offset.empty());
}
