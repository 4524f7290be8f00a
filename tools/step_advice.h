#pragma once
// What `validate` and `run` tell the user about the time step: the stability limits of the scene's springs and
// the step to use instead when the scene's step is past its integrator's limit.
#include <span>
#include <string>

#include "core/model.h"
#include "systems/stability.h"

namespace clothsim::cli {

// The limits for the scene at rest (power iteration: systems/stability.h).
StableSteps scene_stable_steps(const Model& model, std::span<const Vec3> x_rest);

// One sentence naming the remedy: a step below a safe fraction of the integrator's limit, or the implicit
// integrator. Safe step = half the limit: damping and large deflections (which stiffen the transverse
// direction) move the real limit, and the linear limit is the edge of instability, not a comfortable margin.
std::string step_remedy(const Model& model, const StableSteps& limits);

// The validate warning for the scene's step, or "" when it is within its integrator's limit.
std::string step_warning(const Model& model, const StableSteps& limits);

}  // namespace clothsim::cli
