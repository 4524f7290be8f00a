#pragma once
#include <span>

#include "core/model.h"

namespace clothsim {

// The force stage: springs, then external forces, leaving accelerations in ws.f. Every integrator stage calls
// this on the whole system (springs couple particles, so none can be advanced alone).
void eval_forces(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, std::int64_t step,
                 Workspace& ws);

}  // namespace clothsim
