#pragma once
#include <span>

#include "core/model.h"

namespace clothsim {

// Kinetic energy sum(m v^2)/2, J. Summed in fixed blocks in a fixed order: the same bytes at any thread count.
Real kinetic_energy(const Model& model, std::span<const Vec3> v);
// True when every position and velocity is finite.
bool state_is_finite(const State& s);

}  // namespace clothsim
