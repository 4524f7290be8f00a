#pragma once
// timestep="auto": the step chosen from the stability estimate before the run (docs/stability.md, "Automatic
// steps"). The frame loop that rejects and retries steps is sim/frame_stepper.h.
#include <span>
#include <string>

#include "core/model.h"
#include "systems/stability.h"

namespace clothsim {

// The step auto aims for before dividing the frame: step_safety x the integrator's stable step for explicit
// integrators; for backward Euler, which has no stability limit, step_safety x 20 ms (accuracy: its numerical
// damping of a mode of frequency w over a step is 1/(1 + (h w)^2)), the solver's health then halving it.
// 0 when there is none (explicit Euler on an undamped stiff mode).
Real auto_step_target(const SimOptions& options, const StableSteps& limits);

// The largest step the hinges of dihedral bending allow the explicit integrators, which step them explicitly:
// 2 / omega_b with the cloth's highest bending frequency omega_b taken as twice the largest single hinge's
// (estimate_hinge_omega; docs/stability.md, "Dihedral bending"). +inf without hinges. Backward Euler has the
// hinges' Jacobian in its matrix and is not bound by it.
Real hinge_step_limit(const Model& model, std::span<const Vec3> x_rest);

// The explicit integrators' stable steps at rest: the springs' and damping's (power iterations,
// systems/stability.h) with the hinges' bound.
StableSteps model_stable_steps(const Model& model, std::span<const Vec3> x_rest);

// Sets options.dt and options.steps_per_frame for timestep="auto": the largest step that divides a frame evenly and
// does not exceed auto_step_target; min_dt defaults to dt / 1024. Throws Error naming the scene when explicit
// Euler has no stable step.
void choose_auto_step(const Model& model, SimOptions& options, std::span<const Vec3> x_rest,
                      const std::string& scene_path);

}  // namespace clothsim
