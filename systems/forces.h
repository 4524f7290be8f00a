#pragma once
#include <chrono>
#include <span>

#include "core/model.h"
#include "systems/external_forces.h"
#include "systems/normals.h"
#include "systems/parallel.h"
#include "systems/spring_forces.h"
#include "systems/step_result.h"

namespace clothsim {

// The force stage: springs, stitches, hinges, then external forces, leaving accelerations in ws.f. Every integrator stage calls
// this on the whole system (springs couple particles, so none can be advanced alone). Returns one evaluation and
// its wall time (StepCounts::force_evaluations, seconds_forces).
StepCounts eval_forces(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, Real time,
                       Workspace& ws);

// The force stage followed by an integrator's per-particle update: update(i) runs once per particle with the
// acceleration in ws.f[i], and may overwrite x[i] and v[i] (nothing reads them after). With the blocked layout
// (and model.fuse_particle_pass) the external forces and update(i) run inside the spring pass, in the chunk
// that closes particle i, while x, v and f of its neighbourhood are in cache: one sweep over the particles
// instead of three (springs, external forces, update). The bytes are those of eval_forces and a separate pass.
// Returns what eval_forces does (the update counted as force time when it runs inside the pass).
template <class Update>
StepCounts eval_forces_then(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Real time,
                            Workspace& ws, Update&& update) {
  // Stitches and hinges add their forces after the springs, before any particle is final: no fused pass with them.
  if (m.spring_layout != SpringLayout::blocked || !m.fuse_particle_pass || m.stitch_count > 0 || m.hinge_count > 0) {
    const StepCounts counts = eval_forces(m, x, v, time, ws);
    parallel_over(m.particle_count, particle_grain, update);
    return counts;
  }
  const auto t0 = std::chrono::steady_clock::now();
  if (m.needs_normals()) eval_normals(m, x, ws.normal);
  std::span<Vec3> f = ws.f;
  eval_springs_blocked_then(m, x, v, f, [&](Index i) {
    f[i] = external_acceleration(m, i, f[i], x[i], v[i], time, ws.normal);
    update(i);
  });
  // The update is inside the pass: counted as force time (the studies' split is then forces + update).
  StepCounts counts;
  counts.force_evaluations = 1;
  counts.seconds_forces = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return counts;
}

}  // namespace clothsim
