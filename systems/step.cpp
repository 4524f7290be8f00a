#include "systems/step.h"

#include <chrono>
#include <utility>

#include "systems/attachments.h"
#include "systems/collide.h"
#include "systems/forces.h"
#include "systems/integrate_explicit.h"
#include "systems/integrate_implicit.h"
#include "systems/integrate_rk4.h"
#include "systems/strain_limit.h"

namespace clothsim {

void step(const Model& model, const State& in, State& out, Workspace& ws, Real h) {
  const auto t0 = std::chrono::steady_clock::now();
  const double forces_before = ws.seconds_forces, collide_before = ws.seconds_collide;
  switch (model.integrator) {
    case Integrator::euler:
      eval_forces(model, in.x, in.v, in.step, ws);
      integrate_euler(in.x, in.v, ws.f, h, out.x, out.v);
      break;
    case Integrator::symplectic:
      integrate_symplectic(model, in, out, ws, h);
      break;
    case Integrator::rk4:
      integrate_rk4(model, in, out, ws, h);
      break;
    case Integrator::implicit:
      integrate_implicit(model, in, out, ws, h);
      break;
  }
  apply_attachments(model, in, out, h);
  collide(model, in, out, ws, h);
  if (model.strain_limited) apply_strain_limit(model, out, ws, h);
  out.time = in.time + h;
  out.step = in.step + 1;
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ws.seconds_integrate += total - (ws.seconds_forces - forces_before) - (ws.seconds_collide - collide_before);
}

void step_frame(const Model& model, State& state, State& scratch, Workspace& ws) {
  for (int k = 0; k < model.steps_per_frame; ++k) {
    step(model, state, scratch, ws, model.dt);
    std::swap(state, scratch);
  }
}

}  // namespace clothsim
