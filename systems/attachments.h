#pragma once
// The attachment stage of a step (core/attachments.h): each attached particle is placed at its bound point of
// its collider triangle at the end of the step, with the velocity that carries it there from the start.
#include "core/model.h"

namespace clothsim {

// Runs after the integrator, before the collide stage, so that collisions and the strain limit see the attached
// particles (pins, infinite mass) where the collider puts them. h: the step from `in` to `out`; s holds the
// animated colliders' frames (CollisionScratch::collider_frames).
void apply_attachments(const Model& model, const CollisionScratch& s, const State& in, State& out, Real h);

}  // namespace clothsim
