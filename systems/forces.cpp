#include "systems/forces.h"

#include "systems/bend_forces.h"
#include "systems/stitch_forces.h"

namespace clothsim {

StepCounts eval_forces(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, Real time,
                       Workspace& ws) {
  const auto t0 = std::chrono::steady_clock::now();
  eval_springs(model, x, v, ws.f);
  if (model.stitch_count > 0) eval_stitches(model, x, v, ws.stitch_rest, ws.stitch_pull, ws.f);
  if (model.hinge_count > 0) eval_hinges(model, x, ws.hinge_force, ws.f);
  if (model.needs_normals()) eval_normals(model, x, ws.normal);
  apply_external_forces(model, x, v, time, ws.normal, ws.f);
  StepCounts counts;
  counts.force_evaluations = 1;
  counts.seconds_forces = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return counts;
}

}  // namespace clothsim
