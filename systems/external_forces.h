#pragma once
#include <span>

#include "core/model.h"

namespace clothsim {

// Turns the accumulated spring forces f into accelerations, adding gravity and the constant external
// acceleration, the seeded random acceleration of this step, air damping -c v, and Provot's wind
// F = k_w A [n.(u_w - v)] n (A the particle's lumped area, n its unit normal). Pinned particles get zero.
void apply_external_forces(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v,
                           std::int64_t step, std::span<const Vec3> normal, std::span<Vec3> f);

}  // namespace clothsim
