#include "sim/step_advice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "systems/auto_step.h"

namespace clothsim::sim {
namespace {

std::string seconds(Real s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g s", s);
  return buf;
}

// The step to advise: auto's target, never above half a step that diverged.
Real advised_step(const SimOptions& m, const StableSteps& limits, Real diverged_step) {
  Real advised = auto_step_target(m, limits);
  if (diverged_step > 0) advised = std::min(advised, 0.5 * diverged_step);
  return advised;
}

// What sets an explicit integrator's limit: the springs (with their damping) or the dihedral hinges.
std::string limit_cause(const StableSteps& limits, Real limit) {
  return limit == limits.hinges ? "the dihedral hinges' bending" : "these springs and their damping";
}

}  // namespace

std::string step_remedy(const SimOptions& m, const StableSteps& limits, Real diverged_step) {
  const std::string alternatives = ", timestep=\"auto\", or integrator=\"implicit\"";
  const Real limit = stable_step_limit(limits, m.integrator);
  switch (m.integrator) {
    case Integrator::euler:
      if (!(limit > 0)) {
        SimOptions symplectic = m;
        symplectic.integrator = Integrator::symplectic;
        return "explicit Euler has no stable step for these springs (a stiff mode has no damping): use "
               "integrator=\"symplectic\" with a time step below " + seconds(advised_step(symplectic, limits, 0)) +
               ", or integrator=\"implicit\"";
      }
      [[fallthrough]];
    case Integrator::symplectic:
    case Integrator::rk4: {
      // Advice to take a step the run already takes would send the user in circles: a run that diverged well
      // below the limit has another cause.
      if (diverged_step > 0 && diverged_step < 0.5 * limit)
        return "the step is already below half the stability limit " + seconds(limit) +
               ", so a smaller one will not help: look for another cause, such as a cloth starting inside a "
               "collider or crossing itself";
      const Real advised = advised_step(m, limits, diverged_step);
      char safety[32];
      std::snprintf(safety, sizeof safety, "%g", m.step_safety);
      return "use a time step below " + seconds(advised) +
             (advised < auto_step_target(m, limits) ? " (half the step that diverged; the estimated limit is " +
                                                          seconds(limit) + ")"
                                                    : " (stepSafety " + std::string(safety) +
                                                          " x the limit " + seconds(limit) + " for " +
                                                          limit_cause(limits, limit) + ")") +
             alternatives;
    }
    case Integrator::implicit:
      break;
  }
  const Real step = diverged_step > 0 ? diverged_step : m.dt;
  // The run's guard does not say which check failed the step (an unconverged solve, or a converged one whose
  // linearisation about the step's start went too far); both are cured by shorter steps.
  return "backward Euler is stable at any step for springs, but each step linearises the forces about its start "
         "and this one went too far: use a time step below " + seconds(0.25 * step) +
         ", timestep=\"auto\" (which rejects such steps and retries them smaller), or newtonIterations=\"3\"; "
         "a cloth this soft for its load may need a higher stiffness or maxStrain";
}

std::string step_warning(const SimOptions& m, const StableSteps& limits) {
  if (m.integrator == Integrator::implicit) return "";
  const Real limit = stable_step_limit(limits, m.integrator);
  if (std::isinf(limit) || m.dt <= auto_step_target(m, limits)) return "";
  const char* names[] = {"explicit Euler", "symplectic Euler", "RK4", ""};
  return "warning: the step " + seconds(m.dt) + (m.dt >= limit ? " exceeds the " : " is close to the ") +
         names[int(m.integrator)] + " limit " + seconds(limit) + " for " + limit_cause(limits, limit) + "; " +
         step_remedy(m, limits);
}

}  // namespace clothsim::sim
