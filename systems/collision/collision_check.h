#pragma once
// Independent checks for --stats and the tests: they share no code with the collide stage's broad or narrow
// phase (exact distances and ray parity through uniform grids of their own, mesh_check.h; a sweep over x and
// segment-triangle tests).
#include <span>

#include "core/model.h"

namespace clothsim {

// Smallest distance from a cloth vertex to collider c (negative inside a sphere or below a plane), m. Collider
// meshes use the positions of s.collider_x1 (the end of the last step) and an exact point-triangle distance.
Real min_collider_distance(const Model& model, std::span<const Vec3> x, const CollisionScratch& s, Index c);

// Cloth vertices inside collider c: inside a sphere, below a plane, inside a closed mesh (ray parity);
// 0 for an open mesh, where inside is not defined.
Index count_inside(const Model& model, std::span<const Vec3> x, const CollisionScratch& s, Index c);

// Pairs (cloth triangle, triangle of collider mesh c, at s.collider_x1) that intersect: an edge of one crosses
// the other. The penetration check for open meshes, where inside is not defined; 0 for spheres, planes and
// closed meshes (count_inside checks those).
Index count_collider_crossings(const Model& model, std::span<const Vec3> x, const CollisionScratch& s, Index c);

// Pairs of cloth triangles that share no vertex, nor a sewn pair of vertices (CollisionModel::joined), and
// intersect (an edge of one crosses the other).
Index count_intersecting_triangles(const Model& model, std::span<const Vec3> x);

// True when segment p-q crosses triangle (a, b, c) (Moller & Trumbore 1997, with the ray clipped to [0, 1]).
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace clothsim
