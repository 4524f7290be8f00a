#pragma once
// Small models for the integrator, stability and strain-limit tests: a spring between two particles (built by
// hand: build_model lumps mass from triangles, and two particles have none) and grid sheets built the normal way.
#include <vector>

#include "core/build_model.h"
#include "core/model.h"
#include "systems/step.h"
#include "tests/support/scene_fixtures.h"

namespace clothsim::test {

// One spring along x between particle 0 at the origin and particle 1 at `length` (scene_fixtures.h's oscillator,
// generalised): a zero mass pins that particle. No gravity, no air damping, CG tolerance 1e-12.
inline BuiltScene two_particle_spring(Real mass0, Real mass1, Real ke, Real kd, Real rest, Real length,
                                      Integrator integrator) {
  BuiltScene s = two_particle_spring(ke, kd, mass1 > 0 ? mass1 : 1, rest, length - rest, integrator);
  Model& m = s.model;
  m.particle_inv_mass = {mass0 > 0 ? 1 / mass0 : 0, mass1 > 0 ? 1 / mass1 : 0};
  m.pinned.clear();
  for (Index i = 0; i < 2; ++i)
    if (m.particle_inv_mass[i] == 0) m.pinned.push_back(i);
  s.options.solver.cg_tolerance = 1e-12;
  s.options.dt = 1e-3;
  s.options.end_frame = 2;
  return s;
}

struct GridSpec {
  int nx = 8, ny = 8;
  Real size = 1;          // m, square
  Real stiffness = 1000;  // N/m
  Real damping = 0;       // N s/m
  Real bend_scale = 1;
  Real density = 0.2;     // kg/m^2
  Real max_strain = 0;
  std::vector<Index> pins;
  Vec3 gravity{0, -9.81, 0};
  Integrator integrator = Integrator::symplectic;
};

// A grid sheet turned into the XY plane with row 0 (vertices 0 .. nx-1) on top at y = size/2, so pinning
// vertices of row 0 hangs it under gravity -y. Built by build_model.
inline BuiltScene grid_sheet(const GridSpec& g) {
  SceneDesc scene = grid_scene(g.nx, g.ny, g.size, g.integrator);
  scene.simulation.gravity = g.gravity;
  scene.simulation.cg_tolerance = 1e-8;
  ClothDesc& c = scene.cloths[0];
  c.stiffness = g.stiffness;
  c.damping = g.damping;
  c.bend_scale = g.bend_scale;
  c.density = g.density;
  c.max_strain = g.max_strain;
  c.pins = g.pins;
  c.transform.rotate = Vec3(90, 0, 0);
  return build(scene);
}

// Advances `steps` steps of h with the options' integrator; returns what they did, summed.
inline StepCounts run_steps(const Model& m, const SimOptions& o, State& s, Workspace& ws, Real h, int steps) {
  State scratch = s;
  StepCounts counts;
  for (int k = 0; k < steps; ++k) {
    counts.add(step(m, o, s, scratch, ws, h).counts);
    std::swap(s, scratch);
  }
  return counts;
}

// Moves every particle by up to scale/2 per axis and gives it a velocity in [-0.5, 0.5)^3, from a fixed
// pseudo-random sequence (a 64-bit LCG), so no spring sits at rest and every run sees the same state.
inline void perturb_state(State& s, std::uint64_t seed, Real scale) {
  std::uint64_t r = seed;
  auto next = [&r] {
    r = r * 6364136223846793005ull + 1442695040888963407ull;
    return double(r >> 11) / double(1ull << 53) - 0.5;
  };
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    s.x[i] += scale * Vec3(next(), next(), next());
    s.v[i] = Vec3(next(), next(), next());
  }
}

}  // namespace clothsim::test
