#pragma once
#include <span>

#include "core/math.h"

namespace clothsim {

// Explicit (forward) Euler: x' = x + h v, v' = v + h a. First order; unstable for undamped springs at any h.
void integrate_euler(std::span<const Vec3> x, std::span<const Vec3> v, std::span<const Vec3> a, Real h,
                     std::span<Vec3> x_out, std::span<Vec3> v_out);
// Symplectic (semi-implicit) Euler: v' = v + h a, x' = x + h v'. First order; stable for h < 2/omega_max.
void integrate_symplectic(std::span<const Vec3> x, std::span<const Vec3> v, std::span<const Vec3> a, Real h,
                          std::span<Vec3> x_out, std::span<Vec3> v_out);

}  // namespace clothsim
