#pragma once
// What `validate` and `run` tell the user about the time step, from the stability limits of the scene's springs,
// damping and hinges (model_stable_steps, systems/auto_step.h): the step to use instead when the scene's step is
// past its integrator's limit or diverged.
#include <span>
#include <string>

#include "core/model.h"
#include "systems/stability.h"

namespace clothsim::sim {

// One sentence naming the remedy: a step below the advised one (stepSafety x the integrator's damped limit, the
// step timestep="auto" aims for), timestep="auto", or the implicit integrator. diverged_step > 0 is a step that
// has just diverged: the advice is then at most half of it, whatever the estimate says.
std::string step_remedy(const SimOptions& options, const StableSteps& limits, Real diverged_step = 0);

// The validate warning for the scene's step, or "" when it is within the advised step.
std::string step_warning(const SimOptions& options, const StableSteps& limits);

}  // namespace clothsim::sim
