#pragma once
// A Model built from explicit particles and springs, without a mesh: the closed-form test problems of the
// studies and tests (a mass on a spring, a chain), whose frequencies are known exactly.
#include <vector>

#include "core/build_model.h"

namespace clothsim {

struct SpringSystemDesc {
  std::vector<Vec3> positions;          // rest positions, m (particles)
  std::vector<Real> masses;             // kg, 0 for a pinned particle (particles)
  std::vector<Index> spring_a, spring_b;  // particle pairs (springs); rest lengths from `positions`
  Real stiffness = 0;                   // N/m, every spring
  Real damping = 0;                     // N s/m along every spring
  Vec3 gravity{0, 0, 0};                // m/s^2
  Integrator integrator = Integrator::symplectic;
};

// Throws Error for a spring naming a missing particle or joining coincident ones.
BuiltScene build_spring_system(const SpringSystemDesc& desc);

}  // namespace clothsim
