#pragma once
// What one step tells the frame loop besides the state it wrote: whether its result can be trusted, and what it
// did (the figures `run --stats` and the studies sum). Kept out of the Workspace, which is scratch.
#include <algorithm>
#include <cstdint>

#include "core/collision_model.h"

namespace clothsim {

// The implicit step's health (systems/integrate_implicit.h): what it did, and whether its result can be trusted.
struct SolveRecord {
  int cg_iterations = 0;         // summed over the Newton iterations of the step
  Real cg_residual = 0;          // |r|/|b| at the end of the last solve
  int factorizations = 0;        // numeric Cholesky factorisations (preconditioner="cholesky")
  bool converged = true;         // every linear solve reached cg_tolerance (none stopped at cg_max_iterations)
  bool newton_diverged = false;  // a Newton correction left a larger backward-Euler residual than the one before
  // The solver's own health; the strain a step made is checked by the frame loop (sim/frame_stepper.h).
  bool failed() const { return !converged || newton_diverged; }
};

// What steps did, summed over any number of them.
struct StepCounts {
  std::int64_t force_evaluations = 0;  // of the whole system (RK4: four a step)
  std::int64_t cg_iterations = 0;      // implicit
  std::int64_t strain_sweeps = 0;      // strain-limit sweeps (systems/strain_limit.h)
  std::int64_t contacts = 0;           // contacts found by the first collision pass
  std::int64_t guarded = 0;            // vertices put back on a collider surface (systems/collision/collider_guard.h)
  ZoneFigures zones;                   // the impact zones (systems/collision/impact_zones.h)
  double seconds_forces = 0, seconds_integrate = 0, seconds_collide = 0;  // wall time of the stages

  void add(const StepCounts& o) {
    force_evaluations += o.force_evaluations;
    cg_iterations += o.cg_iterations;
    strain_sweeps += o.strain_sweeps;
    contacts += o.contacts;
    guarded += o.guarded;
    zones.add(o.zones);
    seconds_forces += o.seconds_forces;
    seconds_integrate += o.seconds_integrate;
    seconds_collide += o.seconds_collide;
  }
};

// failed: the step's state is not to be trusted although it may be finite (a linear solve stopped at its
// iteration cap short of its tolerance). Any integrator or stage can set it; sim/frame_stepper.h rejects the
// step and retries it smaller.
struct StepResult {
  bool failed = false;
  bool strain_limit_exhausted = false;  // failed because the strain limit stopped at its sweep cap, unmet
  SolveRecord solve;  // the implicit solve's record (untouched for the explicit integrators)
  StepCounts counts;
  // For timestep="auto" with collisions (sim/frame_stepper.h tells the collide stage's strain jumps from the
  // integrator's): the largest spring strain before the collide stage (-1: not measured), and the farthest travel
  // over the step of a collider-mesh vertex or of a cloth particle as the integrator moved it (h |v|, before the
  // stitch and strain limits), m; and the farthest a collider-mesh vertex alone moved, m.
  Real strain_before_collide = -1;
  Real travel = 0, collider_travel = 0;
};

}  // namespace clothsim
