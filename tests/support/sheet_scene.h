#pragma once
// The fixed scene every benchmark, the CI gate and the peer comparison share: an n x n grid sheet, 1 m square,
// 1 kg, hanging from its two corners on the first row, no collisions (docs/performance.md).
#include "core/build_model.h"
#include "core/scene_desc.h"

namespace clothsim::bench {

inline SceneDesc sheet_scene(int n, Integrator integrator, Real timestep = 1e-4) {
  SceneDesc s;
  s.path = "<bench sheet>";
  s.simulation.timestep = timestep;
  s.simulation.fps = 24;
  s.simulation.integrator = integrator;
  s.forces.air_damping = 0.1;
  ClothDesc c;
  c.name = "sheet";
  c.save_name = "sheet";
  c.grid_nx = c.grid_ny = n;
  c.grid_w = c.grid_h = 1;
  c.density = 1;  // kg/m^2 over 1 m^2
  c.stiffness = 1000;
  c.damping = 0.1;
  c.bend_scale = 0.1;
  c.pins = {0, n - 1};
  c.transform.translate = Vec3(0, 1, 0);
  s.cloths.push_back(c);
  return s;
}

inline BuiltScene build_sheet(int n, Integrator integrator, Real timestep = 1e-4) {
  const SceneDesc s = sheet_scene(n, integrator, timestep);
  return build_model(s, {make_cloth_grid(s.cloths[0])});
}

}  // namespace clothsim::bench
