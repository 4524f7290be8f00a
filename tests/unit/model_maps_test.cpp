// Model building from per-vertex parameters (as io/cloth_maps hands them over), against hand-counted figures.
#include <doctest/doctest.h>

#include "core/build_model.h"

using namespace clothsim;

namespace {

// A 3 x 3 grid, 2 m x 2 m: four 1 m^2 squares, eight triangles of 0.5 m^2. Each square (a, b / c, d) splits
// along b-c, so vertex 0 touches 1 triangle, vertex 2 touches 2, the centre vertex 4 touches 6.
BuiltScene build_grid(const VertexParams& params, bool mass_per_vertex = false, Real shear_scale = 0.5) {
  SceneDesc scene;
  ClothDesc cloth;
  cloth.grid_nx = cloth.grid_ny = 3;
  cloth.grid_w = cloth.grid_h = 2;
  cloth.shear_scale = shear_scale;
  cloth.mass_per_vertex = mass_per_vertex;
  scene.cloths = {cloth};
  MeshData mesh = make_cloth_grid(cloth);
  mesh.params = params;
  return build_model(scene, {mesh});
}

std::vector<Real> one_to_nine(Real scale) {
  std::vector<Real> v;
  for (int i = 1; i <= 9; ++i) v.push_back(scale * i);
  return v;
}

}  // namespace

TEST_CASE("a density map is lumped by area: each triangle gives a corner its density times a third of its area") {
  VertexParams p;
  p.density = one_to_nine(1);  // vertex i: i + 1 kg/m^2
  const Model m = build_grid(p).model;
  CHECK(1 / m.particle_inv_mass[0] == doctest::Approx(1 * 0.5 / 3));      // one triangle
  CHECK(1 / m.particle_inv_mass[2] == doctest::Approx(3 * 2 * 0.5 / 3));  // two triangles
  CHECK(1 / m.particle_inv_mass[4] == doctest::Approx(5 * 6 * 0.5 / 3));  // six triangles
}

TEST_CASE("a mass map gives kg per vertex as written, whatever the area") {
  VertexParams p;
  p.mass = one_to_nine(0.1);
  p.pinned.assign(9, 0);
  p.pinned[8] = 1;
  const Model m = build_grid(p, true).model;
  for (int i = 0; i < 8; ++i) CHECK(1 / m.particle_inv_mass[i] == doctest::Approx(0.1 * (i + 1)));
  CHECK(m.particle_inv_mass[8] == 0);  // pinned by the pins map
  CHECK(m.pinned == std::vector<Index>{8});
}

TEST_CASE("a spring takes the mean of its ends' stiffness and damping times its kind's scale") {
  VertexParams p;
  p.stiffness = one_to_nine(100);
  p.damping = one_to_nine(0.01);
  p.thickness = one_to_nine(0.001);
  const Model m = build_grid(p).model;
  // Grid spring order at (0, 0): structural 0-1, structural 0-3, shear 0-4, shear 1-3, flex 0-2, flex 0-6.
  REQUIRE(m.spring_a[2] == 0);
  REQUIRE(m.spring_b[2] == 4);
  CHECK(m.spring_ke[0] == doctest::Approx(0.5 * (100 + 200)));
  CHECK(m.spring_ke[2] == doctest::Approx(0.5 * (100 + 500) * 0.5));  // shear scale 0.5
  CHECK(m.spring_ke[4] == doctest::Approx(0.5 * (100 + 300)));        // flex, bend scale 1
  CHECK(m.spring_kd[5] == doctest::Approx(0.5 * (0.01 + 0.07)));
  CHECK(m.particle_thickness[7] == doctest::Approx(0.008));
  CHECK(m.cloths[0].thickness == doctest::Approx(0.009));  // the largest, for collision bounds
  CHECK_FALSE(m.spring_ke.uniform());

  // Without maps (and one scale for every kind) each field stays one scalar: model no more than the scene needs.
  const Model plain = build_grid({}, false, 1.0).model;
  CHECK(plain.spring_ke.uniform());
  CHECK(plain.spring_kd.uniform());
  CHECK(plain.particle_thickness.uniform());
  CHECK(plain.spring_ke.bytes() == sizeof(Real));
}
