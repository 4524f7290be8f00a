#include "tools/step_advice.h"

#include <cmath>
#include <cstdio>

namespace clothsim::cli {
namespace {

std::string seconds(Real s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g s", s);
  return buf;
}

}  // namespace

StableSteps scene_stable_steps(const Model& model, std::span<const Vec3> x_rest) {
  return stable_steps(estimate_omega_max(model, x_rest));
}

std::string step_remedy(const Model& m, const StableSteps& limits) {
  switch (m.integrator) {
    case Integrator::euler:
      return "explicit Euler has no stable step for undamped springs: use integrator=\"symplectic\" with a time "
             "step below " + seconds(0.5 * limits.symplectic) + ", or integrator=\"implicit\"";
    case Integrator::symplectic:
    case Integrator::rk4:
      // Advice to take a step the run already takes would send the user in circles.
      if (m.dt < 0.5 * stable_step_limit(limits, m.integrator))
        return "the step is already below half the stability limit " +
               seconds(stable_step_limit(limits, m.integrator)) +
               ", so a smaller one will not help: look for another cause, such as a cloth starting inside a " +
               "collider or crossing itself";
      return "use a time step below " + seconds(0.5 * stable_step_limit(limits, m.integrator)) +
             " (half the limit " + seconds(stable_step_limit(limits, m.integrator)) + "), or integrator=\"implicit\"";
    case Integrator::implicit:
      break;
  }
  return "backward Euler is stable at any step for springs; the linear solve failed: use a time step below " +
         seconds(0.25 * m.dt) + " or a tighter cgTolerance";
}

std::string step_warning(const Model& m, const StableSteps& limits) {
  if (m.integrator == Integrator::implicit || limits.omega_max == 0) return "";
  const Real limit = stable_step_limit(limits, m.integrator);
  if (m.dt < limit) return "";
  if (m.integrator == Integrator::euler) return "warning: " + step_remedy(m, limits);
  const char* name = m.integrator == Integrator::symplectic ? "symplectic Euler" : "RK4";
  return "warning: the step " + seconds(m.dt) + " exceeds the " + name + " limit " + seconds(limit) +
         " for these springs; " + step_remedy(m, limits);
}

}  // namespace clothsim::cli
