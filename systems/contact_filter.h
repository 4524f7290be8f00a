#pragma once
// Collider contacts held inside the implicit solve: Baraff & Witkin 1998 §5.3's constraint filter. A particle the
// last collide stage found on a collider is held at dv . n = 0 along that contact's normal in the next solve, so
// its springs cannot pull it back into the body; a particle whose forces pull it off the body is not held, so
// cloth lifts off freely. Without it, a contact pushes one vertex out and not its neighbours, and the next solve
// pulls it straight back in (docs/stability.md, "Collider contacts held in the solve").
//
// The collide stage sums each particle's collider contacts in fixed point (note_collider_contact,
// systems/collision/response.h) and gather_contact_holds turns the sums into State::contact, so the held set is
// the same bytes at any thread count and travels with the state through checkpoints. The hold's impulse is the
// normal force of Coulomb friction, applied after the solve: the collide stage never sees the approach the hold
// stopped, so it cannot rub on it.
#include <span>

#include "core/model.h"
#include "systems/implicit_system.h"

namespace clothsim {

// Cosine below which a particle's contact normals disagree too much to share one hold (a vertex in a crease
// between two surfaces): |sum of n| / count < this leaves it free, to the collide stage.
inline constexpr Real contact_filter_agreement = 0.7;

// The sparse Cholesky preconditioner's stand-in for a hold: a stiffness this many times the particle's mean diagonal
// entry along n, so the factor's inverse is close to the held system's on the filtered subspace. Without it, CG with
// a fresh factor needed 7 to 33 iterations on the dress with 4 to 55 holds, against 1 with none.
inline constexpr Real hold_stiffness_factor = 1e6;
// The block the factor adds for particle i's hold (zero when it is free).
inline Sym3 hold_block(const Workspace& ws, Index i, const Sym3& diagonal) {
  const std::vector<Vec3>& normal = ws.collision.filter_normal;
  if (normal.empty() || !(normal[i].squaredNorm() > 0)) return {};
  const Real k = hold_stiffness_factor * (diagonal.xx + diagonal.yy + diagonal.zz) / 3;
  return Sym3::from(k * normal[i] * normal[i].transpose());
}

// Zeroes the contact sums before the collide stage's first proximity pass.
void clear_contact_holds(const Model& m, CollisionScratch& s);
// out.contact from the sums: where the particle touched a collider and its normals agree, the mean normal, collider
// velocity and friction; else zero. Sizes out.contact on its first use.
void gather_contact_holds(const Model& m, const CollisionScratch& s, State& out);

// The holds for this step's solves from in.contact (free particles only); false when there are none or the filter
// is off for this workspace. Zeroes held_impulse, which the step's solves add their holds' impulses to.
bool prepare_contact_filter(const Model& m, const State& in, Workspace& ws);
// w -= n (n . w) at every held particle: the filter S of Baraff & Witkin's modified PCG.
void filter_held(const Workspace& ws, std::span<Vec3> w);
// Before a solve, with ws.cg_r = b: releases each hold whose particle the right-hand side already pushes off the
// body (n . b > 0: its forces, springs included, pull it away), keeps n . b of the others in held_rhs and filters
// ws.cg_r.
void start_filtered_solve(Workspace& ws);
// After the solve, y = ws.cg_x: adds each hold's impulse lambda = n . (A y - b) to held_impulse (the step's solves
// summed). Uses ws.cg_q.
void finish_filtered_solve(const Model& m, std::span<const Vec3> x, Real h, ImplicitLayout layout, Workspace& ws);
// Coulomb friction of the holds on out (after the solves, before the strain limit): each held particle pressed on
// the body (impulse lambda > 0) loses up to mu lambda / m of its velocity along the surface relative to the
// collider, sticking when that is all of it; its position follows (x = x0 + h v).
void apply_held_friction(const Model& m, const State& in, State& out, const Workspace& ws, Real h);

}  // namespace clothsim
