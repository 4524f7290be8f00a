#include "sim/frame_stepper.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "systems/diagnostics.h"
#include "systems/spring_forces.h"
#include "systems/stability.h"
#include "systems/step.h"

namespace clothsim::sim {

namespace {
constexpr int max_level = 40;  // halvings; min_dt stops far earlier

void count_accepted(FrameSteps& report, Real h) {
  ++report.taken;
  report.smallest = report.taken == 1 ? h : std::min(report.smallest, h);
  report.largest = std::max(report.largest, h);
}

// Adds a step's figures, accepted or rejected, to the frame's.
void record(FrameSteps& report, const StepResult& result, Integrator integrator) {
  report.counts.add(result.counts);
  if (integrator == Integrator::implicit) report.solves.push_back(result.solve);
}
}  // namespace

namespace {
// Whether a step that started at largest strain strain_before reached the collide stage without a strain jump
// (measured for timestep="auto" with collisions only), so that any jump it ends with is that stage's.
bool jump_left_to_collide(const StepResult& result, Real strain_before) {
  return result.strain_before_collide >= 0 && result.strain_before_collide <= strain_before + FrameStepper::strain_jump;
}
}  // namespace

bool collide_stage_jump(const Model& m, const StepResult& result, Real strain_before, bool at_floor) {
  return jump_left_to_collide(result, strain_before) &&
         (at_floor || result.travel <= FrameStepper::travel_fraction * m.collision.max_thickness);
}

StepVerdict failure_verdict(const StepResult& result, bool strain_jumped) {
  if (result.strain_limit_exhausted) return StepVerdict::strain_limit;
  if (result.failed) return StepVerdict::failed_solve;
  return strain_jumped ? StepVerdict::strain_jump : StepVerdict::none;
}

const char* verdict_name(StepVerdict v) {
  switch (v) {
    case StepVerdict::none: return "accepted";
    case StepVerdict::failed_solve:
      return "its linear solve stopped at cgMaxIterations or a Newton correction raised the residual";
    case StepVerdict::non_finite: return "non-finite positions or velocities";
    case StepVerdict::strain_jump: return "the largest strain jumped by more than 0.1 in one step";
    case StepVerdict::energy_jump: return "the mechanical energy rose past its bound";
    case StepVerdict::strain_limit: return "the strain limit stopped at its sweep cap with springs past maxStrain";
    case StepVerdict::zones_unresolved: return "the impact zones stopped with pairs still to resolve";
  }
  return "";
}

FrameStepper::FrameStepper(const Model& m, const SimOptions& o, const State& start) : x_start_(start.x) {
  energy_start_ = mechanical_energy(m, start, x_start_);
  energy_bound_ = energy_rise_bound(m, x_start_, o.seconds());
}

Real FrameStepper::current_step(const SimOptions& o) const { return std::ldexp(o.dt, -level_); }

Real FrameStepper::energy_rise(const Model& m, const State& state) const {
  return mechanical_energy(m, state, x_start_) - energy_start_;
}

void FrameStepper::fixed_frame(const Model& m, const SimOptions& o, State& state, State& scratch, Workspace& ws,
                               FrameSteps& report) {
  // Only backward Euler can fail inside a step without leaving non-finite values; its strain check costs a pass
  // over the springs, shared between consecutive steps. Any integrator's strain limit can stop unmet.
  const bool check = o.integrator == Integrator::implicit;
  Real strain = check ? max_spring_strain(m, state.x) : 0;
  for (int k = 0; k < o.steps_per_frame; ++k) {
    const StepResult result = step(m, o, state, scratch, ws, o.dt);
    record(report, result, o.integrator);
    std::swap(state, scratch);
    count_accepted(report, o.dt);
    if (!check && !result.strain_limit_exhausted) continue;
    const Real strain_after = max_spring_strain(m, state.x);
    const StepVerdict verdict = failure_verdict(result, strain_after > strain + strain_jump);
    if (verdict != StepVerdict::none && report.failed++ == 0)
      report.first_failure = {verdict, o.dt, strain, strain_after, result.solve};
    strain = strain_after;
  }
}

int FrameStepper::floor_level(const SimOptions& o) {
  int level = 0;
  while (level < max_level && std::ldexp(o.dt, -(level + 1)) >= o.min_dt) ++level;
  return level;
}

bool FrameStepper::jump_stays_at_floor(const Model& m, const SimOptions& o, const State& start, Workspace& ws,
                                       const StepResult& result, Real strain, Real jump, FrameSteps& report,
                                       Real& probe_strain) {
  if (!jump_left_to_collide(result, strain)) return false;
  if (probe_.x.size() != start.x.size()) probe_ = start;
  probe_result_ = step(m, o, start, probe_, ws, std::ldexp(o.dt, -floor_level_));
  record(report, probe_result_, o.integrator);
  // One step more than the frame keeps, either way: the probe, or the whole step it replaces.
  ++report.rejected;
  if (probe_result_.failed || !state_is_finite(probe_) || !jump_left_to_collide(probe_result_, strain)) return false;
  probe_strain = max_spring_strain(m, probe_.x);
  return probe_strain - strain >= floor_keep_ratio * jump;
}

bool FrameStepper::advance_frame(const Model& m, const SimOptions& o, State& state, State& scratch, Workspace& ws,
                                 FrameSteps& report) {
  report = {};
  if (!o.auto_step) {
    fixed_frame(m, o, state, scratch, ws, report);
    return true;
  }
  level_ = 0;
  easy_ = 0;
  fast_grow_ = false;
  floor_level_ = floor_level(o);
  Real strain = max_spring_strain(m, state.x);
  // Position inside the frame in steps of the current level; the frame ends at steps_per_frame << level.
  std::int64_t pos = 0;
  while (pos < (std::int64_t(o.steps_per_frame) << level_)) {
    const Real h = current_step(o);
    const StepResult result = step(m, o, state, scratch, ws, h);
    record(report, result, o.integrator);
    StepVerdict verdict = StepVerdict::none;
    Real strain_after = strain;
    // A strain jump that the collide stage made in a step where neither a collider nor the cloth moved by more
    // than a quarter of the thickness, or at minTimestep, is kept whole: a smaller step would not push the cloth
    // much less. One that a probe at the floor step repeats is kept as that probe's step (where halving would
    // have ended). Either then goes on to the energy check and, passing it, is reported as a fixed step's is; the
    // step grows back at the next aligned point.
    bool kept = false, probe_kept = false;
    const bool at_floor = level_ >= floor_level_;
    if (result.failed) verdict = failure_verdict(result, false);
    else if (!state_is_finite(scratch)) verdict = StepVerdict::non_finite;
    else if ((strain_after = max_spring_strain(m, scratch.x)) > strain + strain_jump) {
      Real probe_strain = 0;
      if (collide_stage_jump(m, result, strain, at_floor)) kept = true;
      else if (jump_stays_at_floor(m, o, state, ws, result, strain, strain_after - strain, report, probe_strain)) {
        kept = probe_kept = true;
        strain_after = probe_strain;
      } else verdict = StepVerdict::strain_jump;
    }
    if (verdict == StepVerdict::none && !(energy_rise(m, probe_kept ? probe_ : scratch) <= energy_bound_))
      verdict = StepVerdict::energy_jump;
    // Impact zones that stopped with pairs left (docs/stability.md, "Automatic steps") in a step where a collider
    // moved by more than travel_fraction of the thickness: a zone holding collider vertices takes their motion
    // whole, and a smaller step splits that motion. Against still colliders halving did not resolve the zones
    // (the sewn dress, docs/garments.md), so the cloth's own travel does not count. At the floor step it is kept.
    if (verdict == StepVerdict::none && !probe_kept && !at_floor && result.counts.zones.unresolved > 0 &&
        result.collider_travel > travel_fraction * m.collision.max_thickness)
      verdict = StepVerdict::zones_unresolved;
    if (verdict != StepVerdict::none) {
      // Rejected: state still holds the step's start, untouched (step wrote into scratch only).
      ++report.rejected;
      report.last_rejection = verdict;
      if (at_floor) return false;
      ++level_;
      pos *= 2;
      easy_ = 0;
      fast_grow_ = false;
      continue;
    }
    if (probe_kept) {
      pos <<= floor_level_ - level_;
      level_ = floor_level_;
      std::swap(state, probe_);
    } else {
      std::swap(state, scratch);
    }
    const Real h_taken = current_step(o);
    if (kept && report.failed++ == 0)
      report.first_failure = {StepVerdict::strain_jump, h_taken, strain, strain_after,
                              probe_kept ? probe_result_.solve : result.solve};
    strain = strain_after;
    ++pos;
    count_accepted(report, h_taken);
    // Grow back after a run of easy steps, when the doubled step still ends on the frame; at each aligned point
    // after a kept jump, since no failure made the step smaller.
    if (kept) fast_grow_ = true;
    if (++easy_ >= (fast_grow_ ? 1 : grow_after) && level_ > 0 && pos % 2 == 0) {
      --level_;
      pos /= 2;
      easy_ = 0;
    }
  }
  return true;
}

}  // namespace clothsim::sim
