#pragma once
// In-memory scenes for the tests: built through core::build_model, as the CLI does, without XML.
#include "core/build_model.h"
#include "core/model.h"

namespace clothsim::test {

// A scene without cloths or colliders, stepped at `timestep` one step per frame.
inline SceneDesc stepped_scene(Integrator integrator, Real timestep) {
  SceneDesc s;
  s.path = "<test>";
  s.simulation.integrator = integrator;
  s.simulation.timestep = timestep;
  s.simulation.fps = 1.0 / timestep;
  return s;
}

inline SceneDesc grid_scene(int nx, int ny, Real size, Integrator integrator, Real timestep = 1e-3) {
  SceneDesc s = stepped_scene(integrator, timestep);
  ClothDesc c;
  c.name = "sheet";
  c.grid_nx = nx;
  c.grid_ny = ny;
  c.grid_w = c.grid_h = size;
  s.cloths.push_back(c);
  return s;
}

inline BuiltScene build(const SceneDesc& s) {
  std::vector<MeshData> meshes;
  for (const ClothDesc& c : s.cloths) meshes.push_back(make_cloth_grid(c));
  return build_model(s, meshes);
}

// Two particles and one spring along x: particle 0 pinned at the origin, particle 1 of mass m at rest length
// L + stretch. Its motion is the closed-form oscillator m x'' = -k (x - L) - kd x'.
inline BuiltScene two_particle_spring(Real k, Real kd, Real m, Real rest, Real stretch, Integrator integrator) {
  BuiltScene b;
  Model& md = b.model;
  b.options.integrator = integrator;
  md.particle_count = 2;
  md.particle_inv_mass = {0.0, 1.0 / m};
  md.pinned = {0};
  md.spring_count = 1;
  md.spring_a = {0};
  md.spring_b = {1};
  md.spring_rest = {rest};
  md.spring_ke = ParamField(k);
  md.spring_kd = ParamField(kd);
  md.spring_kind_total[int(SpringKind::edge)] = 1;
  md.particle_spring_offset = {0, 1, 2};
  md.particle_spring_index = {0, ~0};
  md.particle_tri_offset = {0, 0, 0};
  md.gravity = Vec3::Zero();
  b.state = make_state(md, {Vec3::Zero(), Vec3(rest + stretch, 0, 0)});
  return b;
}

}  // namespace clothsim::test
