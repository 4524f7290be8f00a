#pragma once
// Strain limiting (Provot 1995 §5): after the integrator, springs stretched beyond their cloth's maxStrain are
// pulled back, and the velocities are changed by the same displacement / h, so x' = x + h v' still holds and the
// next step does not undo the correction. docs/stability.md, "Strain limiting", gives the algorithm and figures.
#include <functional>
#include <span>

#include "core/model.h"

namespace clothsim {

// Strain tolerance guaranteed on exit when the iteration converges: every limited spring ends with
// (|d| - rest)/rest <= maxStrain + strain_limit_tolerance. docs/stability.md, "Strain limiting".
inline constexpr Real strain_limit_tolerance = 1e-3;
inline constexpr int strain_limit_max_iterations = 500;
// Over-relaxation of the Gauss-Seidel sweeps after the first (successive over-relaxation of the projections:
// each moves its spring omega times the way to the limit; 0 < omega < 2 keeps every projection non-expansive
// towards the feasible set, so the sweeps still converge). 1.8 took the fewest sweeps on the peer sheet without
// moving the cloth further (docs/stability.md, "Strain limiting", gives each value's sweeps).
inline constexpr Real strain_limit_relaxation = 1.8;

// The largest strain excess (|d| - rest)/rest - maxStrain over the limited springs (model.spring_colour_spring);
// -inf when there are none.
Real strain_limit_excess(const Model& model, std::span<const Vec3> x);

// Corrects out.x and out.v in place (h the step just taken). Nothing happens when every limited spring is within
// its limit + strain_limit_tolerance / 2. Otherwise: (1) each tethered particle farther from its pin than its
// tether_length is moved onto that sphere (Kim et al. 2012); (2) Gauss-Seidel sweeps over the spring colours:
// each spring longer than (1 + maxStrain) rest is shortened to it, the correction split between its ends by
// inverse mass (a pinned end does not move), in colour order, each colour in parallel; the first sweep projects
// exactly, later ones over-relax by strain_limit_relaxation; until every limited spring is within the limit +
// strain_limit_tolerance / 2, or strain_limit_max_iterations sweeps. Same bytes at any thread count. Returns
// the sweeps taken (0 when the tethers alone were enough).
int apply_strain_limit(const Model& model, State& out, Real h);

// A particle a pass after a sweep moved (safe to call from several threads), and such a pass.
using MovedParticle = std::function<void(Index)>;
using ContactHoldPass = std::function<void(State&, const MovedParticle&)>;

// The strain limit again after the collide stage, which pushes single vertices out of a collider and stretches
// their springs past maxStrain. set_contact_planes records, for every particle the collide stage left on a
// collider (out.contact's normal n nonzero), its plane offset n . x (contact_offset, particle_count).
// apply_strain_limit_on_contacts first puts every such particle back in front of its plane n . x >= offset, then
// runs the strain limit's sweeps with the same projection after each: a contact may slide along its collider, not
// into it, and its neighbours are pulled to it rather than it to them. Velocities move with positions. Returns the
// sweeps taken (0 when the limit was met). Where the contacts themselves hold a spring past its limit (cloth
// pinched between two colliders), the sweeps stop at strain_limit_max_iterations unmet. `hold`, when given, runs
// after the planes every time they do (the cloth-cloth holds, systems/collision/cloth_holds.h) and reports each
// particle it moves to its second argument, so that the next sweep projects the springs at it again.
void set_contact_planes(const Model& model, const State& out, std::span<Real> contact_offset);
int apply_strain_limit_on_contacts(const Model& model, State& out, Real h, std::span<const Real> contact_offset,
                                   const ContactHoldPass& hold = {});

// Whether every limited spring is within its limit + strain_limit_tolerance / 2: what apply_strain_limit ends
// with unless it stopped at strain_limit_max_iterations (a limit the cloth cannot meet in one step, or at all).
bool strain_limit_met(const Model& model, std::span<const Vec3> x);

}  // namespace clothsim
