#pragma once
// The last word against collider meshes in a step whose strain limit runs after the collide stage
// (systems/step.cpp). Those rounds keep each contact in front of its one contact plane, but a vertex may slide
// along that plane into another part of the body (cloth between the arm and the chest), and a vertex with no
// plane (its contact normals disagreed) is free. So after them every cloth vertex is tested against the collider
// triangles within collider_guard_reach thicknesses, and one found behind the surface is taken back out of it.
#include "core/model.h"
#include "core/triangle_distance.h"

namespace clothsim {

// How far behind a collider surface a vertex is looked for, in cloth thicknesses: the rounds move contacts by
// a few millimetres at most (the Rumba's deepest crossing was 4 mm with 3 mm thick cloth).
inline constexpr Real collider_guard_reach = 2;
// How far in front of the surface a vertex found behind it is put, in its thickness: the next step's proximity
// pass, not this one, eases it out to the thickness (collider_separation_speed).
inline constexpr Real collider_guard_margin = 0.1;

// Whether point x lies behind the surface of collider triangle `tri` (corners at the end of the step), judged at
// its closest point q (closest_point_and_weights) by the angle-weighted normal of the feature q lies on (face,
// edge or vertex: its nonzero weights; Baerentzen & Aanaes 2005), so that a point beside an edge or a corner is
// judged by both sides.
bool behind_collider_triangle(const Model& model, const CollisionScratch& s, Index tri, const Vec3& x,
                              const TrianglePoint& q);

// Moves every movable cloth vertex of out that lies behind its nearest collider-mesh triangle (within the reach)
// out of the collider: back along the straight way from where the collide stage left it (s.collided_x, when that
// is at least the margin outside) to the first point the margin outside, found by bisection; else onto that
// nearest surface plus the margin. It loses the velocity into the surface and takes the surface nearest to its
// new place as its contact
// (out.contact: the outward normal, the collider's velocity there over the step h, the friction), so that the
// strain limit's planes and the next solve's filter hold it. Uses the collider side of the broad phase the step's
// collide stage built (its boxes cover the colliders' end positions). Returns the vertices moved. Each vertex is
// handled alone: the same bytes at any thread count.
Index guard_collider_surfaces(const Model& model, State& out, const CollisionScratch& s, Real h);

}  // namespace clothsim
