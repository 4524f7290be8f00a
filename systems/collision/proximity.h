#pragma once
// Per-element proximity maths of the collision stage (Bridson, Fedkiw & Anderson 2002, §6.1): no threading,
// testable alone.
#include <algorithm>
#include <cmath>

#include "core/collision_model.h"
#include "core/triangle_distance.h"

namespace clothsim {

struct TriangleProximity {
  Real d = 0;      // signed distance of the point from the triangle's plane along n, m
  Vec3 n;          // unit normal, counter-clockwise (b - a) x (c - a)
  Real w[3] = {};  // barycentric weights of the projected point
};

// Point p against triangle (a, b, c): barycentrics from the 2x2 normal equations of the projection, solved by
// Cramer's rule, accepted within [-delta, 1 + delta] with delta = h / (longest edge) so that a point just past
// an edge still counts (Bridson et al. 2002 §6.1). False for a point outside or a degenerate triangle.
inline bool vertex_triangle_proximity(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Real h,
                                      TriangleProximity& out) {
  const Vec3 e1 = b - a, e2 = c - a, r = p - a;
  const Real a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2);
  const Real det = a11 * a22 - a12 * a12;
  if (!(det > 1e-12 * a11 * a22)) return false;
  const Real b1 = e1.dot(r), b2 = e2.dot(r);
  const Real u = (b1 * a22 - a12 * b2) / det, v = (a11 * b2 - a12 * b1) / det;
  const Real longest = std::sqrt(std::max({a11, a22, (c - b).squaredNorm()}));
  const Real delta = h / longest;
  const Real w0 = 1 - u - v;
  if (w0 < -delta || u < -delta || v < -delta || w0 > 1 + delta || u > 1 + delta || v > 1 + delta) return false;
  out.n = e1.cross(e2).normalized();
  out.d = out.n.dot(r);
  out.w[0] = w0;
  out.w[1] = u;
  out.w[2] = v;
  return true;
}

struct EdgeProximity {
  Real s = 0, t = 0;  // closest points p1 + s (p2 - p1) and q1 + t (q2 - q1)
  Real d = 0;         // their distance, m
  Vec3 n;             // unit direction from the second edge's point to the first's
};

// Closest points of segments p1p2 and q1q2 (Ericson, Real-Time Collision Detection §5.1.9), the edge-edge test
// of Bridson et al. 2002 §6.1. When the segments touch, n falls back to the normal of the two edges. False for
// degenerate or parallel-and-touching edges, where no direction is defined.
inline bool edge_edge_proximity(const Vec3& p1, const Vec3& p2, const Vec3& q1, const Vec3& q2, EdgeProximity& out) {
  const Vec3 d1 = p2 - p1, d2 = q2 - q1, r = p1 - q1;
  const Real a = d1.dot(d1), e = d2.dot(d2), f = d2.dot(r);
  if (!(a > 0) || !(e > 0)) return false;
  const Real c = d1.dot(r), b = d1.dot(d2);
  const Real denom = a * e - b * b;
  Real s = denom > 1e-12 * a * e ? std::clamp((b * f - c * e) / denom, Real(0), Real(1)) : 0;
  Real t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, Real(0), Real(1));
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, Real(0), Real(1));
  }
  const Vec3 gap = (p1 + s * d1) - (q1 + t * d2);
  out.s = s;
  out.t = t;
  out.d = gap.norm();
  if (out.d > 1e-12) {
    out.n = gap / out.d;
  } else {
    const Vec3 cr = d1.cross(d2);
    if (!(cr.squaredNorm() > 0)) return false;
    out.n = cr.normalized();
  }
  return true;
}

inline bool boxes_overlap(const Aabb& a, const Aabb& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

}  // namespace clothsim
