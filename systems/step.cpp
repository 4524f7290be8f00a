#include "systems/step.h"

#include <algorithm>
#include <chrono>
#include <span>

#include "systems/attachments.h"
#include "systems/collision/cloth_holds.h"
#include "systems/collision/collider_guard.h"
#include "systems/collision/collide.h"
#include "systems/forces.h"
#include "systems/integrate_explicit.h"
#include "systems/integrate_implicit.h"
#include "systems/integrate_rk4.h"
#include "systems/reduce.h"
#include "systems/spring_forces.h"
#include "systems/stitch_forces.h"
#include "systems/strain_limit.h"

namespace clothsim {
namespace {

// The farthest any of the points moved from `from` to `to`, m; the same bytes at any thread count.
Real largest_move(std::span<const Vec3> from, std::span<const Vec3> to) {
  return deterministic_reduce(
      Index(to.size()), particle_grain, Real(0), [&](Index i) { return (to[i] - from[i]).norm(); },
      [](Real a, Real b) { return std::max(a, b); });
}

// Runs limit() (a strain limit returning its sweeps), then, while the stitch pass still moves a gap, the stitch
// pass and limit() again, up to `rounds` rounds: the strain limit reopens gaps the stitch pass closed
// where a seam's panels are short of their partners, and alternating settles both (docs/garments.md, "Sewing").
// Adds every round's sweeps to total; returns the last limit's.
template <class Limit>
int limit_with_stitches(const Model& model, Workspace& ws, State& out, Real h, Real t, std::int64_t& total, int rounds,
                        Limit&& limit) {
  int sweeps = limit();
  total += sweeps;
  // A limit that stopped at its cap (contacts pinching a spring) will not do better in another round.
  for (int round = 1; round < rounds && model.stitch_count > 0 && sweeps < strain_limit_max_iterations;
       ++round) {
    if (apply_stitch_limit(model, ws.stitch_rest, out, h, t) == 0) break;
    sweeps = limit();
    total += sweeps;
  }
  return sweeps;
}

}  // namespace

StepResult step(const Model& model, const SimOptions& options, const State& in, State& out, Workspace& ws, Real h) {
  // A run's first step with the implicit solve's contact filter: find what the cloth already touches, so that the
  // first solve holds it (a garment that starts on its body would otherwise be pulled into it for one step).
  if (!ws.collision.acc_hold.empty() && in.contact.size() != std::size_t(model.particle_count)) {
    State primed = in;
    prime_contact_holds(model, primed, ws, h);
    return step(model, options, primed, out, ws, h);
  }
  using clock = std::chrono::steady_clock;
  StepResult result;
  const auto t0 = clock::now();
  if (model.stitch_count > 0) set_stitch_rest(model, in.x, in.v, in.time + h, h, ws.stitch_rest, ws.stitch_pull);
  switch (options.integrator) {
    case Integrator::euler:
      result.counts = eval_forces(model, in.x, in.v, in.time, ws);
      integrate_euler(in.x, in.v, ws.f, h, out.x, out.v);
      break;
    case Integrator::symplectic:
      result.counts = integrate_symplectic(model, in, out, ws, h);
      break;
    case Integrator::rk4:
      result.counts = integrate_rk4(model, in, out, ws, h);
      break;
    case Integrator::implicit:
      result = integrate_implicit(model, options.solver, in, out, ws, h);
      break;
  }
  // What the automatic step needs to tell the collide stage's strain jumps from the integrator's
  // (sim/frame_stepper.h); nothing for a fixed step. The cloth's travel is the integrator's h|v| alone: the stitch
  // and strain limits' corrections do not shrink with the step, and in a pinch they alone would count as motion.
  const bool measure = options.auto_step && model.collision.enabled;
  if (measure) result.travel = largest_move(in.x, out.x);
  apply_attachments(model, ws.collision, in, out, h);
  const Real t = in.time + h;
  if (model.stitch_count > 0) apply_stitch_limit(model, ws.stitch_rest, out, h, t);
  if (model.strain_limited) {
    const int sweeps = limit_with_stitches(model, ws, out, h, t, result.counts.strain_sweeps, stitch_strain_rounds,
                                           [&] { return apply_strain_limit(model, out, h); });
    // Springs left past maxStrain after the last sweep: the step did not do what the scene asked.
    if (sweeps >= strain_limit_max_iterations && !strain_limit_met(model, out.x)) {
      result.failed = true;
      result.strain_limit_exhausted = true;
    }
  }
  if (measure) result.strain_before_collide = max_spring_strain(model, out.x);
  const auto t1 = clock::now();
  const CollideCounts collided = collide(model, in, out, ws, h);
  // The collide stage pushes single vertices out of a collider and stretches their springs; the strain limit
  // then pulls the neighbours after them, keeping every collider contact in front of its contact plane and every
  // cloth-cloth pair within the thickness at least as far apart as the stage left it (so that it cannot pull a
  // seam or a fold through another layer), and alternates with the stitch pass as before, for fewer rounds. This
  // runs where the collide stage records the collider contacts (the implicit solve's contact filter); a spring
  // the contacts alone hold stretched (a pinch) is left for the step control to judge.
  if (!ws.collision.contact_offset.empty()) {
    CollisionScratch& s = ws.collision;
    std::copy(out.x.begin(), out.x.end(), s.collided_x.begin());
    set_contact_planes(model, out, s.contact_offset);
    gather_cloth_holds(model, in, out, s);
    const auto hold = [&](State& held, const MovedParticle& moved) { apply_cloth_holds(model, held, s, h, moved); };
    const auto limit = [&] {
      limit_with_stitches(model, ws, out, h, t, result.counts.strain_sweeps, stitch_strain_rounds_after_collide,
                          [&] { return apply_strain_limit_on_contacts(model, out, h, s.contact_offset, hold); });
    };
    limit();
    // Vertices the rounds slid behind another part of a collider go back out of it, held there by a plane of
    // their own while the limit pulls their neighbours after them; the second guard has the last word.
    result.counts.guarded = guard_collider_surfaces(model, out, s, h);
    if (result.counts.guarded > 0) {
      set_contact_planes(model, out, s.contact_offset);
      limit();
      result.counts.guarded += guard_collider_surfaces(model, out, s, h);
    }
  }
  // The colliders' positions over the step, as the collide stage placed them.
  if (measure) {
    result.collider_travel = largest_move(ws.collision.collider_x0, ws.collision.collider_x1);
    result.travel = std::max(result.travel, result.collider_travel);
  }
  const auto t2 = clock::now();
  out.time = in.time + h;
  out.step = in.step + 1;
  result.counts.contacts = collided.contacts;
  result.counts.zones = collided.zones;
  result.counts.seconds_collide = std::chrono::duration<double>(t2 - t1).count();
  result.counts.seconds_integrate = std::chrono::duration<double>(t1 - t0).count() - result.counts.seconds_forces;
  return result;
}

}  // namespace clothsim
