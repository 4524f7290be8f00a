// max_spring_strain, the strain the step check, the frame guard and --stats read, over the stretch springs only:
// a mesh's bend springs are left out (a knife pleat folded flat at rest made one 0.04 mm long on the real dress,
// and the fold's smallest opening read as 36 %), and a grid's flex springs never exceed its structural ones.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "systems/spring_forces.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;

namespace {

// Largest strain over every spring, by hand: what max_spring_strain measured before bend springs were left out.
Real largest_over_all(const Model& m, const std::vector<Vec3>& x) {
  Real best = 0;
  for (Index s = 0; s < m.spring_count; ++s)
    best = std::max(best, ((x[m.spring_b[s]] - x[m.spring_a[s]]).norm() - m.spring_rest[s]) / m.spring_rest[s]);
  return best;
}

}  // namespace

TEST_CASE("the strain the checks read leaves out a mesh's bend springs: a pleat folded flat at rest, opened") {
  // Edge 0-1 along x, 10 mm; vertices 2 and 3 both 8 mm above its middle, 0.04 mm apart in z: the two triangles
  // lie folded onto each other, and the bend spring 2-3 is 0.04 mm long.
  MeshData mesh;
  mesh.positions = {{0, 0, 0}, {0.01, 0, 0}, {0.005, 0.008, 0}, {0.005, 0.008, 4e-5}};
  mesh.tri_index = {0, 1, 2, 1, 0, 3};
  SceneDesc s = test::stepped_scene(Integrator::implicit, 1e-3);
  ClothDesc c;
  c.name = "pleat";
  c.obj = "<mesh>";
  s.cloths.push_back(c);
  const BuiltScene b = build_model(s, std::vector<MeshData>{mesh});
  const Model& m = b.model;
  REQUIRE(m.spring_count == 6);
  CHECK(m.spring_kind_total[int(SpringKind::bend)] == 1);
  REQUIRE(m.cloths.size() == 1);
  CHECK(m.cloths[0].bend_springs == 1);
  CHECK(m.spring_rest[5] == doctest::Approx(4e-5).epsilon(1e-12));  // the bend spring is the last

  // Open the fold by 0.014 mm: the bend spring reads 35 %, the edges 0-3 and 1-3 hardly move.
  std::vector<Vec3> x = b.state.x;
  x[3].z() = 5.4e-5;
  const Real slant = std::hypot(0.005, 0.008);
  const Real edge = (std::sqrt(slant * slant + 5.4e-5 * 5.4e-5) - std::sqrt(slant * slant + 4e-5 * 4e-5)) /
                    std::sqrt(slant * slant + 4e-5 * 4e-5);
  CHECK(largest_over_all(m, x) == doctest::Approx(0.35).epsilon(1e-9));
  CHECK(max_spring_strain(m, x) == doctest::Approx(edge).epsilon(1e-6));
  CHECK(max_spring_strain(m, x) < 1e-5);

  // Stretch edge 0-1 by 1 %: that is the largest strain of the cloth's edges.
  x = b.state.x;
  x[1].x() = 0.0101;
  CHECK(max_spring_strain(m, x) == doctest::Approx(0.01).epsilon(1e-12));
}

TEST_CASE("a grid's flex springs never stretch more than its structural ones: the same strain over every spring") {
  const BuiltScene b = test::build(test::grid_scene(12, 9, 1.0, Integrator::implicit));
  const Model& m = b.model;
  REQUIRE(m.spring_kind_total[int(SpringKind::flex)] > 0);
  CHECK(m.cloths[0].bend_springs == 0);
  std::mt19937 rng(7);
  std::normal_distribution<Real> jiggle(0, 0.02);  // a fifth of the 0.09 m spacing
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec3> x = b.state.x;
    for (Vec3& p : x) p += Vec3(jiggle(rng), jiggle(rng), jiggle(rng));
    CAPTURE(trial);
    CHECK(max_spring_strain(m, x) == largest_over_all(m, x));
  }
}
