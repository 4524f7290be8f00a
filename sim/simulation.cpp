#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "sim/step_advice.h"
#include "systems/auto_step.h"
#include "systems/cholesky_preconditioner.h"
#include "systems/strain_limit.h"
#include "systems/diagnostics.h"
#include "systems/spring_forces.h"
#include "systems/stability.h"

namespace clothsim::sim {

Simulation::Simulation(BuiltScene built, ColliderTrack track)
    : model_(std::move(built.model)),
      options_(built.options),
      state_(std::move(built.state)),
      scratch_(state_),
      ws_(make_workspace(model_, options_)),
      track_(std::move(track)),
      stepper_(model_, options_, state_),
      next_frame_(options_.start_frame),
      last_strain_(max_spring_strain(model_, state_.x)) {}

void Simulation::resume(State state, int frame, const CholeskyRenewal& renewal) {
  state_ = std::move(state);
  ws_.cholesky_renewal = renewal;
  scratch_ = state_;
  next_frame_ = frame + 1;
  last_strain_ = max_spring_strain(model_, state_.x);
}

std::string describe_overrun(const LimitOverrun& o) {
  if (o.frames == 0) return {};
  char text[500];
  std::snprintf(text, sizeof text, "%lld of %lld frames ended with springs past maxStrain, by up to %.3g (frame %d, "
                "largest strain %.4g): contacts held them stretched where the strain limit after the collide stage "
                "could not meet both (docs/stability.md, \"After the collide stage\")",
                static_cast<long long>(o.frames), static_cast<long long>(o.stepped), o.worst_excess, o.worst_frame,
                o.worst_strain);
  return text;
}

std::string describe_failure(const SimOptions& opt, const StepFailure& f, int frame) {
  const SolverOptions& solver = opt.solver;
  char text[400];
  if (f.verdict == StepVerdict::failed_solve && !f.solve.converged)
    // With the Cholesky factor CG stalls only where the factorisation failed (not positive definite in floating
    // point) and the solve fell back to block-Jacobi: a smaller step makes the matrix better conditioned.
    std::snprintf(text, sizeof text, "frame %d: CG stopped at relative residual %.3g above cgTolerance %.3g "
                  "(cgMaxIterations %d): raise cgMaxIterations or %s", frame, f.solve.cg_residual,
                  solver.cg_tolerance, solver.cg_max_iterations,
                  solver.preconditioner == Preconditioner::cholesky ? "take a smaller timestep"
                                                                    : "use preconditioner=\"cholesky\"");
  else if (f.verdict == StepVerdict::strain_limit)
    std::snprintf(text, sizeof text, "frame %d: the strain limit stopped after %d sweeps with springs still past "
                  "maxStrain (largest strain %.3g): take a smaller timestep, or raise maxStrain", frame,
                  strain_limit_max_iterations, f.strain_after);
  else if (f.verdict == StepVerdict::failed_solve)
    std::snprintf(text, sizeof text, "frame %d: a Newton correction raised the backward-Euler residual: take a "
                  "smaller timestep", frame);
  else if (f.verdict == StepVerdict::strain_jump && opt.auto_step)
    // Kept by timestep="auto": the collide stage's pushes, with everything nearly still or as large at minTimestep
    // (collide_stage_jump).
    std::snprintf(text, sizeof text, "frame %d: the largest spring strain went from %.3g to %.3g in the collision "
                  "stage of one step of %.3g s, with colliders and cloth nearly still or as large at minTimestep, so "
                  "a smaller step would not help: cloth caught between surfaces closer than two thicknesses, or a "
                  "collider through it; a smaller thickness may help", frame, f.strain_before, f.strain_after,
                  f.step);
  else
    std::snprintf(text, sizeof text, "frame %d: the largest spring strain went from %.3g to %.3g in one step of "
                  "%.3g s, past the %.2g a step can be trusted with: take a smaller timestep or more "
                  "newtonIterations", frame, f.strain_before, f.strain_after, f.step, FrameStepper::strain_jump);
  return text;
}

FrameReport Simulation::advance_frame() {
  FrameReport r;
  r.frame = next_frame_++;
  bool stepped = true;
  if (r.frame > options_.start_frame) {
    track_.prepare(model_, r.frame, ws_.collision);
    // The Cholesky factor kept from step to step is dropped at a frame's start: a checkpoint cannot hold it, so a
    // run resumed from one then preconditions, and steps, as the whole run did.
    forget_cholesky_factor(ws_);
    stepped = stepper_.advance_frame(model_, options_, state_, scratch_, ws_, r.steps);
    totals_.add(r.steps.counts);
  }
  // The divergence guard (docs/stability.md): every frame is checked before anyone writes it.
  const bool finite = state_is_finite(state_);
  const Real energy_rise = finite ? stepper_.energy_rise(model_, state_) : 0;
  const Real strain = finite ? max_spring_strain(model_, state_.x) : 0;
  const bool torn = strain - last_strain_ > frame_strain_jump;
  if (!stepped || !finite || !(energy_rise <= stepper_.energy_bound()) || torn) {
    char reason[200];
    if (!stepped)
      std::snprintf(reason, sizeof reason, "a step below minTimestep %.3g s was rejected: %s", options_.min_dt,
                    verdict_name(r.steps.last_rejection));
    else if (finite && torn)
      std::snprintf(reason, sizeof reason, "the largest spring strain rose from %.3g to %.3g within one frame, "
                    "past the %.2g no cloth stretches in a frame", last_strain_, strain, frame_strain_jump);
    else if (finite)
      std::snprintf(reason, sizeof reason, "the mechanical energy rose by %.3g J, past the bound %.3g J",
                    energy_rise, stepper_.energy_bound());
    else
      std::snprintf(reason, sizeof reason, "non-finite positions or velocities");
    const Real failed_step = stepper_.current_step(options_);
    const std::string remedy =
        step_remedy(options_, model_stable_steps(model_, stepper_.start_positions()), failed_step);
    char text[600];
    std::snprintf(text, sizeof text, "frame %d, step %lld: the simulation diverged (%s); no frame from here on "
                  "was written. The step was %.3g s: %s.", r.frame, static_cast<long long>(state_.step), reason,
                  failed_step, remedy.c_str());
    r.diverged = true;
    r.divergence = text;
    return r;
  }
  r.max_strain = last_strain_ = strain;
  if (model_.strain_limited) r.strain_excess = std::max(Real(0), strain_limit_excess(model_, state_.x));
  if (r.frame > options_.start_frame) {
    ++overrun_.stepped;
    if (r.strain_excess > strain_limit_tolerance) {
      ++overrun_.frames;
      if (r.strain_excess > overrun_.worst_excess) {
        overrun_.worst_frame = r.frame;
        overrun_.worst_excess = r.strain_excess;
        overrun_.worst_strain = strain;
      }
    }
  }
  r.kinetic_energy = kinetic_energy(model_, state_.v);
  if (r.steps.failed > 0 && failed_steps_ == 0)
    first_failure_ = describe_failure(options_, r.steps.first_failure, r.frame);
  failed_steps_ += r.steps.failed;
  return r;
}

}  // namespace clothsim::sim
