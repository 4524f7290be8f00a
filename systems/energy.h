#pragma once
#include <span>

#include "core/model.h"

namespace clothsim {

// Elastic energy of the springs, sum ke (|d| - rest)^2 / 2, J. Summed in fixed blocks in a fixed order: the
// same bytes at any thread count. With kinetic_energy it is the energy the stability study watches.
Real spring_potential_energy(const Model& model, std::span<const Vec3> x);

}  // namespace clothsim
