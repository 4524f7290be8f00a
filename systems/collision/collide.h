#pragma once
// The collide stage of a step: collider motion, broad phase (spatial hash or BVH), vertex-triangle and
// edge-edge proximity, and the averaged responses, repeated model.collision.iterations times, then the continuous
// passes and the impact zones (Bridson, Fedkiw & Anderson 2002 §6-7). Does nothing for a model without
// collisions. Each concern has its file in systems/collision/: colliders, broad_phase, proximity_pairs,
// continuous_pairs, response, impact_zones.
#include <array>
#include <vector>

#include "core/model.h"
#include "systems/collision/broad_phase.h"
#include "systems/collision/colliders.h"

namespace clothsim {

// What the collide stage of a step found.
struct CollideCounts {
  std::int64_t contacts = 0;  // contacts of the first proximity pass
  ZoneFigures zones;          // what the impact zones did
};

// The step from `in` (start) to `out` (integrated, changed in place) of length h.
CollideCounts collide(const Model& model, const State& in, State& out, Workspace& ws, Real h);

// The collider contacts of a state that has none yet (the first step of a run with the implicit solve's contact
// filter): the proximity passes' detection against the colliders at the end of a step of length h, responses
// discarded, so that the first solve already holds a garment that starts on its body (systems/contact_filter.h).
void prime_contact_holds(const Model& model, State& state, Workspace& ws, Real h);

// For tests and benchmarks: every proximity pair of the current configuration found through one broad phase,
// {0, vertex, prim} for vertex-triangle, {1, edge, edge} for edge-edge, {2, cloth triangle, collider vertex}
// and {3, cloth edge, collider edge} against collider meshes, sorted. build_broad_phase must have
// run (and for bvh, the model must hold a BVH).
std::vector<std::array<Index, 3>> list_proximities(const Model& model, const State& in, const State& out,
                                                   CollisionScratch& s, BroadMode mode);
// The pairs of the latest detection pass (s.contacts), listed and sorted as list_proximities lists them.
std::vector<std::array<Index, 3>> list_contacts(const CollisionScratch& s);

}  // namespace clothsim
