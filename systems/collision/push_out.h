#pragma once
// Cloth that starts inside a closed collider mesh (a start pose with interpenetration). The proximity pass sees
// only vertices within the thickness (plus the step's motion) of the surface, and the continuous pass ignores
// crossings that start inside, so such vertices would stay inside for good. The first step a workspace takes
// finds them by ray parity (Jordan curve theorem: an odd number of crossings along a ray means inside); every step
// then moves each towards its nearest point on that collider's surface by at most deep_push_speed * h, until
// it lies one thickness outside, where the proximity pass takes over (docs/scene-format.md, "Colliders").
#include "core/model.h"

namespace clothsim {

// Largest speed of the push-out, m/s: a vertex 3 cm deep is out within 0.06 s, slowly enough that the springs
// drag its neighbours along instead of tearing the cloth through the surface.
inline constexpr Real deep_push_speed = 0.5;

// Moves the flagged particles of out (positions; the velocity component pointing deeper is removed). The scan
// costs (cloth vertices inside the collider's box) x (its triangles), once; each flagged vertex then costs the
// collider's triangles per step. Same bytes at any thread count (each particle is handled alone).
void push_out_deep_vertices(const Model& model, const State& in, State& out, CollisionScratch& s, Real h);

}  // namespace clothsim
