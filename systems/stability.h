#pragma once
// Knowing the limits of the explicit integrators, and noticing when a run has left them.
#include <span>

#include "core/model.h"

namespace clothsim {

// Highest natural frequency of the undamped spring system at rest, omega_max = sqrt(lambda_max(M^-1 K)), rad/s,
// K the stiffness matrix -df/dx at rest (sum over springs of ke n n^T in the 2x2 block pattern), pinned
// particles removed. Power iteration on the symmetric M^-1/2 K M^-1/2 from a fixed pseudo-random start, so the
// estimate is the same at any thread count; the Rayleigh quotient is returned (a lower bound on lambda_max,
// and it converges quadratically in the eigenvector error). 0 when nothing moves or no spring is stiff.
Real estimate_omega_max(const Model& model, std::span<const Vec3> x_rest, int max_iterations = 2000,
                        Real tolerance = 1e-7);

// Largest stable steps for undamped linear springs (the stability intervals of the methods on y'' = -omega^2 y):
// symplectic Euler h < 2/omega_max; classical RK4 h < 2 sqrt(2)/omega_max; explicit Euler has none (its
// amplification sqrt(1 + (h omega)^2) exceeds 1 for every h > 0); backward Euler has no limit.
struct StableSteps {
  Real omega_max = 0;
  Real symplectic = 0;  // s, +inf when omega_max is 0
  Real rk4 = 0;         // s
};
StableSteps stable_steps(Real omega_max);
// The limit of the model's integrator: +inf for implicit, 0 for explicit Euler (no stable step).
Real stable_step_limit(const StableSteps& limits, Integrator integrator);

// Total mechanical energy relative to the start, J: kinetic + spring potential sum ke (|d| - rest)^2 / 2
// - sum m g.(x - x_start) (g: gravity plus constant external acceleration). Deterministic sums.
Real mechanical_energy(const Model& model, const State& state, std::span<const Vec3> x_start);

// The largest rise of mechanical_energy over its start value a run may show before it is declared diverged:
// 10 E_scale with E_scale = M (|g| D + |u_wind|^2 / 2 + (sqrt(3) a_random T)^2 / 2) + sum ke (0.1 rest)^2 / 2,
// M the free mass, D the diagonal of the start positions' bounding box, T the run's duration. A passive cloth
// only loses energy; E_scale bounds what gravity, wind and random forcing can feed it, and the spring term
// (10% strain in every spring) keeps the bound positive in a scene with no external force. docs/stability.md.
Real energy_rise_bound(const Model& model, std::span<const Vec3> x_start);

}  // namespace clothsim
