// Initial contact: a cloth that starts closer than its thickness to a collider, or to another cloth, eases out
// at a bounded speed instead of jumping the whole thickness in one step.
#include <doctest/doctest.h>

#include <algorithm>

#include "core/build_collision.h"
#include "core/build_model.h"
#include "core/grid.h"
#include "systems/collision/response.h"
#include "systems/step.h"

using namespace clothsim;

namespace {

// A 5 x 5 sheet, 0.2 m square in the plane y = 0, without gravity; a ground plane 0.1 mm below it and a
// thickness of 5 mm, so the whole sheet starts 4.9 mm inside the thickness.
BuiltScene sheet_on_plane(Real h) {
  SceneDesc s;
  s.path = "<test>";
  s.simulation.timestep = h;
  s.simulation.fps = 1 / h;
  s.simulation.gravity = Vec3::Zero();
  s.simulation.integrator = Integrator::implicit;
  ClothDesc c;
  c.name = "sheet";
  c.grid_nx = c.grid_ny = 5;
  c.grid_w = c.grid_h = 0.2;
  c.thickness = 0.005;
  s.cloths.push_back(c);
  ColliderDesc ground;
  ground.name = "ground";
  ground.shape = ColliderShape::plane;
  ground.point = Vec3(0, -1e-4, 0);
  ground.normal = Vec3(0, 1, 0);
  s.colliders.push_back(ground);
  BuiltScene b = build_model(s, std::vector<MeshData>{make_cloth_grid(c)});
  build_collision(s, std::vector<ColliderMeshes>(1), b.state.x, b.model);
  return b;
}

}  // namespace

TEST_CASE("a sheet starting inside its thickness over a plane rises at collider_separation_speed a pass, then rests") {
  const Real h = 1e-3;
  BuiltScene b = sheet_on_plane(h);
  Workspace ws = make_workspace(b.model, b.options);
  State out = b.state;
  // Two proximity passes a step (collisionIterations 2), each at most 0.1 m/s x 1 ms: 0.2 mm a step, so 4.9 mm
  // take 25 steps.
  const int passes = b.model.collision.iterations;
  REQUIRE(passes == 2);
  const Real per_step = passes * collider_separation_speed * h;
  for (int k = 0; k < 40; ++k) {
    step(b.model, b.options, b.state, out, ws, h);
    Real rise_min = 1, rise_max = 0;
    for (Index i = 0; i < b.model.particle_count; ++i) {
      const Real rise = out.x[i].y() - b.state.x[i].y();
      rise_min = std::min(rise_min, rise);
      rise_max = std::max(rise_max, rise);
    }
    const Real expected = std::clamp(0.0049 - per_step * k, 0.0, per_step);
    CAPTURE(k);
    CHECK(rise_max <= per_step + 1e-12);
    CHECK(rise_min == doctest::Approx(expected).epsilon(1e-7));
    std::swap(b.state, out);
  }
  for (const Vec3& p : b.state.x) CHECK(p.y() == doctest::Approx(0.0049).epsilon(1e-9));
}
