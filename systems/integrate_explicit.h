#pragma once
#include <span>

#include "core/model.h"
#include "systems/step_result.h"

namespace clothsim {

// Explicit (forward) Euler: x' = x + h v, v' = v + h a. First order; unstable for undamped springs at any h.
void integrate_euler(std::span<const Vec3> x, std::span<const Vec3> v, std::span<const Vec3> a, Real h,
                     std::span<Vec3> x_out, std::span<Vec3> v_out);
// Symplectic (semi-implicit) Euler: v' = v + h a, x' = x + h v'. First order; stable for h < 2/omega_max.
// Evaluates the forces of `in` itself, so the update can run inside the spring pass (systems/forces.h).
// Returns its force stage's counts (eval_forces).
StepCounts integrate_symplectic(const Model& model, const State& in, State& out, Workspace& ws, Real h);

}  // namespace clothsim
