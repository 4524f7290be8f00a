#pragma once
// Cloth-cloth contacts held through the strain limit after the collide stage (systems/step.cpp). The collide
// stage leaves no pair crossed that was not crossed at the start of the step; the strain limit and the stitch
// pass after it move vertices again, and on a garment being sewn they pulled seams and pleats through the
// layers next to them (the collide stage's continuous pass cannot see moves made after it). So every cloth-cloth
// pair the stage left within the thickness is held at least as far apart as the stage left it, projected after
// each strain-limit sweep, as collider contacts are held on their planes.
#include <functional>

#include "core/model.h"

namespace clothsim {

// The cloth-cloth proximity pairs of `out` (vertex-triangle and edge-edge, the sides taken from `in`) within the
// thickness and not crossed, into s.cloth_holds with their distances, sorted by kind and indices. Rebuilds the
// cloth's broad phase for `out`. Clears the holds when no cloth collides with a cloth.
void gather_cloth_holds(const Model& model, const State& in, const State& out, CollisionScratch& s);

// Each held pair closer than the collide stage left it (its gap g = n . sum c_k x_k, with c = (1, -w0, -w1, -w2)
// for a vertex and a triangle, (1 - s, s, -(1 - t), -t) for two edges) goes back to that distance d, its
// particles moved along n by lambda c_k / m_k with lambda = (d - g) / sum c_k^2 / m_k (pins and attached
// vertices do not move), velocities by the same displacement / h. Serial, in the holds' order: the same bytes at
// any thread count. Returns the pairs moved; `on_move`, when given, is called with each particle of a moved pair.
Index apply_cloth_holds(const Model& model, State& out, const CollisionScratch& s, Real h,
                        const std::function<void(Index)>& on_move = {});

}  // namespace clothsim
