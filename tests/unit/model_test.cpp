// Model building: uniform parameters stay scalars, CSR adjacency, spring layouts agree bit for bit.
#include <doctest/doctest.h>

#include "core/csr.h"
#include "core/error.h"
#include "systems/spring_forces.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;

TEST_CASE("a uniform parameter stays one scalar, a varying one becomes an array") {
  const BuiltScene uniform = test::build(test::grid_scene(4, 4, 1.0, Integrator::symplectic));
  CHECK(uniform.model.spring_ke.uniform());
  CHECK(uniform.model.spring_ke.bytes() == sizeof(Real));
  CHECK(uniform.model.spring_kd.uniform());
  CHECK(uniform.model.particle_thickness.uniform());
  SceneDesc s = test::grid_scene(4, 4, 1.0, Integrator::symplectic);
  s.cloths[0].bend_scale = 0.25;
  const BuiltScene mixed = test::build(s);
  CHECK_FALSE(mixed.model.spring_ke.uniform());
  Index flex = 0;
  for (Index k = 0; k < mixed.model.spring_count; ++k)
    if (mixed.model.spring_ke[k] == 250) ++flex;
  CHECK(flex == mixed.model.spring_kind_total[int(SpringKind::flex)]);
}

TEST_CASE("every spring appears twice in the incident-spring CSR, once from each end") {
  BuiltScene b = test::build(test::grid_scene(5, 4, 1.0, Integrator::symplectic));
  CHECK(b.model.particle_spring_offset.empty());  // the blocked layout alone does not read it
  build_particle_springs(b.model);
  const Model& m = b.model;
  CHECK(m.particle_spring_offset.back() == 2 * m.spring_count);
  std::vector<int> seen(m.spring_count, 0);
  for (Index i = 0; i < m.particle_count; ++i)
    for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
      const Index e = m.particle_spring_index[k];
      const Index s = e >= 0 ? e : ~e;
      CHECK((e >= 0 ? m.spring_a[s] : m.spring_b[s]) == i);
      ++seen[s];
    }
  for (int c : seen) CHECK(c == 2);
}

TEST_CASE("gather and two-phase spring layouts give the same bits") {
  BuiltScene b = test::build(test::grid_scene(9, 7, 1.0, Integrator::symplectic));
  build_particle_springs(b.model);
  for (std::size_t i = 0; i < b.state.x.size(); ++i) {  // a deterministic, irregular deformation
    b.state.x[i] += 0.01 * Vec3(std::sin(3.0 * i), std::cos(5.0 * i), std::sin(7.0 * i));
    b.state.v[i] = Vec3(std::cos(2.0 * i), 0.5, std::sin(i));
  }
  std::vector<Vec3> f1(b.model.particle_count), f2(b.model.particle_count), scratch(b.model.spring_count);
  eval_springs_gather(b.model, b.state.x, b.state.v, f1);
  eval_springs_two_phase(b.model, b.state.x, b.state.v, f2, scratch);
  Vec3 total = Vec3::Zero();
  for (Index i = 0; i < b.model.particle_count; ++i) {
    CHECK(f1[i] == f2[i]);
    total += f1[i];
  }
  CHECK(total.norm() < 1e-9);  // internal forces cancel (Newton's third law)
}

TEST_CASE("a pin outside the mesh is an error naming the cloth") {
  SceneDesc s = test::grid_scene(3, 3, 1.0, Integrator::symplectic);
  s.cloths[0].pins = {9};
  CHECK_THROWS_WITH_AS(test::build(s), doctest::Contains("pinned vertex 9 is out of range"), Error);
}
