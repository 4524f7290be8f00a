#pragma once
// Bytes held by the arrays a run keeps for its whole length (the target: at most 400 bytes a particle on a
// 1024^2 sheet, docs/performance.md "Memory and loading"). Capacities, not sizes: what is allocated. The
// collision model and its scratch are left out (empty without colliders and self-collision).
#include <cstddef>

#include "core/model.h"

namespace clothsim {

std::size_t model_bytes(const Model& model);          // particle, spring, triangle and cloth (UV) arrays
std::size_t state_bytes(const State& state);          // positions, velocities and collider contacts
std::size_t workspace_bytes(const Workspace& ws);     // forces, normals, RK4 and implicit scratch, strain limit
std::size_t multigrid_bytes(const Multigrid& mg);     // the multigrid preconditioner's levels (part of the above)

}  // namespace clothsim
