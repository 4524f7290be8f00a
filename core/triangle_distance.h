#pragma once
// Point-triangle distance, shared by model building (attachments pick their nearest collider triangle), the
// push-out of deep vertices and the collision stage's independent checks.
#include "core/math.h"

namespace clothsim {

// The closest point to p on a triangle (a, b, c) and its barycentric weights: exact zeros for the corners the
// point is not on, so a zero weight says it lies on an edge (one zero) or at a corner (two).
struct TrianglePoint {
  Vec3 point;
  Vec3 weights;
};

// Ericson, Real-Time Collision Detection §5.1.5: the region of p decides the point and its weights at once.
inline TrianglePoint closest_point_and_weights(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, Vec3(1, 0, 0)};
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, Vec3(0, 1, 0)};
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const Real t = d1 / (d1 - d3);
    return {a + t * ab, Vec3(1 - t, t, 0)};
  }
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, Vec3(0, 0, 1)};
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const Real t = d2 / (d2 - d6);
    return {a + t * ac, Vec3(1 - t, 0, t)};
  }
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const Real t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + t * (c - b), Vec3(0, 1 - t, t)};
  }
  const Real denom = 1 / (va + vb + vc);
  const Real v = vb * denom, w = vc * denom;
  return {a + ab * v + ac * w, Vec3(1 - v - w, v, w)};
}

inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return closest_point_and_weights(p, a, b, c).point;
}

// Exact distance from p to triangle (a, b, c), for the independent checks of --stats.
inline Real point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return (p - closest_point_on_triangle(p, a, b, c)).norm();
}
}  // namespace clothsim
