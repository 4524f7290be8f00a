#pragma once
// How a run steps, kept apart from the physics it steps (Model): the integrator, the step and the frame clock,
// and the implicit solver's settings. make_sim_options takes them from the scene's <simulation>; timestep="auto"
// then sets dt and steps_per_frame (systems/auto_step.h).
#include "core/scene_desc.h"

namespace clothsim {

// The implicit integrator's linear solves (systems/integrate_implicit.h).
struct SolverOptions {
  Real cg_tolerance = 1e-6;      // relative CG residual |r|/|b| to stop at
  int cg_max_iterations = 1000;  // CG iteration cap per linear solve
  int newton_iterations = 1;     // linear solves per step
  Preconditioner preconditioner = Preconditioner::multigrid;  // of the CG (systems/multigrid.h)
  bool contact_filter = true;    // hold collider contacts in the solve (systems/contact_filter.h)
};

struct SimOptions {
  Integrator integrator = Integrator::symplectic;
  Real dt = 0;                 // s, the step actually taken: 1/(fps * steps_per_frame)
  int steps_per_frame = 1;
  bool auto_step = false;      // timestep="auto": dt set by systems/auto_step.h, adapted by sim/frame_stepper.h
  Real step_safety = 0.7;      // auto: fraction of the estimated stable step
  Real min_dt = 0;             // auto: smallest step, s, before the run stops as diverged
  Real fps = 24;
  int start_frame = 1, end_frame = 1;
  SolverOptions solver;

  Real seconds() const { return (end_frame - start_frame) / fps; }  // the run's simulated time
};

SimOptions make_sim_options(const SimulationDesc& sim);

}  // namespace clothsim
