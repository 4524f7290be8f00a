#include "systems/step.h"

#include <chrono>

#include "systems/attachments.h"
#include "systems/collision/collide.h"
#include "systems/forces.h"
#include "systems/integrate_explicit.h"
#include "systems/integrate_implicit.h"
#include "systems/integrate_rk4.h"
#include "systems/stitch_forces.h"
#include "systems/strain_limit.h"

namespace clothsim {

StepResult step(const Model& model, const SimOptions& options, const State& in, State& out, Workspace& ws, Real h) {
  StepResult result;
  const auto t0 = std::chrono::steady_clock::now();
  const double forces_before = ws.seconds_forces, collide_before = ws.seconds_collide;
  switch (options.integrator) {
    case Integrator::euler:
      eval_forces(model, in.x, in.v, in.time, ws);
      integrate_euler(in.x, in.v, ws.f, h, out.x, out.v);
      break;
    case Integrator::symplectic:
      integrate_symplectic(model, in, out, ws, h);
      break;
    case Integrator::rk4:
      integrate_rk4(model, in, out, ws, h);
      break;
    case Integrator::implicit:
      result = integrate_implicit(model, options.solver, in, out, ws, h);
      break;
  }
  apply_attachments(model, ws.collision, in, out, h);
  if (model.stitch_count > 0) apply_stitch_limit(model, out, h, in.time + h);
  // Collisions end the step (Bridson et al. 2002 §7): the strain limit's projections move particles without
  // looking at contacts, so run after collisions they could drag cloth back into a body or another layer.
  if (model.strain_limited) apply_strain_limit(model, out, ws, h);
  collide(model, in, out, ws, h);
  out.time = in.time + h;
  out.step = in.step + 1;
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ws.seconds_integrate += total - (ws.seconds_forces - forces_before) - (ws.seconds_collide - collide_before);
  return result;
}

}  // namespace clothsim
