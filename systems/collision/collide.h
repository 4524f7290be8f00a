#pragma once
// The collide stage of a step: collider motion, broad phase (spatial hash or BVH), vertex-triangle and
// edge-edge proximity, and the averaged responses, repeated model.collision.iterations times
// (Bridson, Fedkiw & Anderson 2002 §7). Does nothing for a model without collisions.
#include <array>
#include <vector>

#include "core/model.h"

namespace clothsim {

// The step from `in` (start) to `out` (integrated, changed in place) of length h.
void collide(const Model& model, const State& in, State& out, Workspace& ws, Real h);

// Collider mesh vertices at the start and end of the step that begins at `time` (s since the start frame) and
// lasts h (animated colliders interpolated linearly between their frames; static ones stay).
void place_colliders(const Model& model, Real time, Real h, CollisionScratch& s);

// Swept, thickness-inflated prim boxes and the query bounds, then the scene's broad phase.
void build_broad_phase(const Model& model, const State& in, const State& out, CollisionScratch& s);

// For tests and benchmarks: every proximity pair of the current configuration found through one broad phase,
// {0, vertex, prim} for vertex-triangle, {1, edge, edge} for edge-edge, {2, cloth triangle, collider vertex}
// and {3, cloth edge, collider edge} against collider meshes, sorted. build_broad_phase must have
// run (and for bvh, the model must hold a BVH).
enum class BroadMode { hash, bvh, brute };
std::vector<std::array<Index, 3>> list_proximities(const Model& model, const State& in, const State& out,
                                                   CollisionScratch& s, BroadMode mode);

}  // namespace clothsim
