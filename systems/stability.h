#pragma once
// Knowing the limits of the explicit integrators, and noticing when a run has left them.
#include <cstdint>
#include <limits>
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

// Two probes of the damped linear system at rest, M u'' = -K u - C u': the stiffest mode (top eigenvector of
// M^-1 K) with its damping rate (Rayleigh quotient of M^-1 C on it), and the most damped mode (top eigenvector
// of M^-1 C) with its frequency. C = sum kd n n^T (the springs' damping, pattern of K) + M (air damping c) +
// the wind's k_w A n n^T (bounded by its largest diagonal k_w A / m). A spring of zero rest length (a stitch)
// has no direction at rest: it counts as ke I and kd I, which bounds ke n n^T for every n. When the springs'
// damping is proportional to their stiffness (one cloth, kd/ke uniform) both probes are the same exact mode.
struct DampedModes {
  Real omega_max = 0;       // rad/s
  Real gamma_of_stiff = 0;  // 1/s, damping rate of the stiffest mode
  Real gamma_max = 0;       // 1/s, largest damping rate
  Real omega_of_damped = 0; // rad/s, frequency of the most damped mode
  // s, a floor under every light mode's explicit-Euler limit gamma_k / omega_k^2: C >= (kd/ke)_min K + c M
  // spring by spring, so u^T C u / u^T K u >= (kd/ke)_min + c / omega_max^2 for every u (c the air damping alone;
  // wind only adds). The two probes miss the mode that meets it where kd/ke differs between springs.
  Real euler_floor = std::numeric_limits<Real>::infinity();
};
DampedModes estimate_modes(const Model& model, std::span<const Vec3> x_rest);

// Largest stable step of one damped mode u'' = -omega^2 u - gamma u' (docs/stability.md derives each):
//   explicit Euler  |1 + h lambda| <= 1: h <= gamma/omega^2 (under-damped), 2/|lambda_max| (over-damped); 0 undamped
//   symplectic      trace/determinant (Jury) conditions: h^2 omega^2 + 2 h gamma < 4, h = 4/(gamma + sqrt(gamma^2 + 4 omega^2))
//   RK4             |1 + z + z^2/2 + z^3/6 + z^4/24| <= 1 at z = h lambda for both roots, by bisection
//   implicit        +inf
Real mode_step_limit(Integrator integrator, Real omega, Real gamma);
// Spectral radius of one step h of the integrator on that mode: its amplitude grows by this factor a step when
// above 1 (implicit: 0, not modelled).
Real mode_amplification(Integrator integrator, Real omega, Real gamma, Real h);

// Largest stable steps of each integrator for the scene's springs and damping: the smaller of the two probes',
// and for explicit Euler not above euler_floor.
struct StableSteps {
  Real omega_max = 0;
  Real gamma_max = 0;   // 1/s
  Real euler = 0;       // s, 0 when some stiff mode is undamped
  Real symplectic = 0;  // s, +inf when omega_max and gamma_max are 0
  Real rk4 = 0;         // s
  // s: the dihedral hinges' bound on the explicit integrators, which step bending explicitly (+inf without hinges;
  // hinge_step_limit, systems/auto_step.h). Backward Euler has their Jacobian in its matrix and no such bound.
  Real hinges = std::numeric_limits<Real>::infinity();
};
StableSteps stable_steps(const DampedModes& modes);
// Undamped springs only: symplectic 2/omega_max, RK4 2 sqrt(2)/omega_max, explicit Euler none.
StableSteps stable_steps(Real omega_max);
// The limit of the model's integrator, the hinges' included: +inf for implicit.
Real stable_step_limit(const StableSteps& limits, Integrator integrator);

// Total mechanical energy relative to the start, J: kinetic + spring potential sum ke (|d| - rest)^2 / 2
// - sum m g.(x - x_start) (g: gravity plus constant external acceleration), plus the hinges' bending energy
// sum k (theta - theta0)^2 where the model has hinges. Deterministic sums.
Real mechanical_energy(const Model& model, const State& state, std::span<const Vec3> x_start);

// The largest rise of mechanical_energy over its start value a run may show before it is declared diverged:
// 10 E_scale with E_scale = M (|g| D + |u_wind|^2 / 2 + (sqrt(3) a_random T)^2 / 2) + sum ke (0.1 rest)^2 / 2,
// M the free mass, D the diagonal of the start positions' bounding box, T the run's duration (s). A passive cloth
// only loses energy; E_scale bounds what gravity, wind and random forcing can feed it, and the spring term
// (10% strain in every spring) keeps the bound positive in a scene with no external force. docs/stability.md.
Real energy_rise_bound(const Model& model, std::span<const Vec3> x_start, Real duration);

// A frame whose largest spring strain rose by more than this (100% of a rest length) has blown up even where the
// energy bound has not yet seen it (an explicit step far past its limit): the run reports it as diverged.
inline constexpr Real frame_strain_jump = 1.0;

// Runs `steps` steps of h from start with the options' integrator; true when it diverged as `clothsim run` judges
// it: non-finite positions or velocities, the mechanical energy risen past energy_rise_bound, or the largest
// spring strain risen by more than frame_strain_jump within a frame (1 / options.fps). For the stability studies
// and tests (allocates its own workspace).
bool run_diverges(const Model& model, const SimOptions& options, const State& start, Real h, std::int64_t steps);

}  // namespace clothsim
