#pragma once
// Provot 1995 §5 deformation constraints: after the integrator, springs stretched beyond their cloth's
// maxStrain are pulled back, and the velocities are changed by the same displacement / h, so x' = x + h v'
// still holds and the next step does not undo the correction.
#include <span>

#include "core/model.h"

namespace clothsim {

// Strain tolerance guaranteed on exit when the iteration converges: every limited spring ends with
// (|d| - rest)/rest <= maxStrain + strain_limit_tolerance. docs/stability.md, "Strain limiting".
inline constexpr Real strain_limit_tolerance = 1e-3;
inline constexpr int strain_limit_max_iterations = 500;

// Corrects out.x and out.v in place (h the step just taken). Jacobi iterations: each over-stretched spring
// proposes to shorten itself to (1 + maxStrain) rest, split between its ends by inverse mass (a pinned end does
// not move); each particle moves by the average of its springs' proposals, gathered over the CSR of incident
// springs, so the result does not depend on the thread count. Returns the iterations taken.
int apply_strain_limit(const Model& model, State& out, Workspace& ws, Real h);

}  // namespace clothsim
