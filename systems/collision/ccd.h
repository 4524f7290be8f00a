#pragma once
// Continuous vertex-triangle detection along the linear trajectories of a step (Provot 1997; Bridson, Fedkiw &
// Anderson 2002 §6.2): the times t in [0, 1] at which the vertex and the triangle are coplanar are the roots of
// the cubic ((b - a) x (c - a)) . (p - a) = 0; a root whose point lies inside the triangle is a collision.
// Edge-edge detection (§4 of the same paper) solves the same cubic for the four edge endpoints; a root at which the
// closest points of the two segments come within a tolerance is a collision.
#include <algorithm>
#include <cmath>

#include "systems/collision/proximity.h"

namespace clothsim {

// Coefficients k0 + k1 t + k2 t^2 + k3 t^3 of the coplanarity cubic for p, a, b, c moving linearly from x0 to x1.
inline void coplanarity_cubic(const Vec3 x0[4], const Vec3 x1[4], Real k[4]) {
  const Vec3 e1 = x0[2] - x0[1], e2 = x0[3] - x0[1], r = x0[0] - x0[1];
  const Vec3 u1 = (x1[2] - x0[2]) - (x1[1] - x0[1]), u2 = (x1[3] - x0[3]) - (x1[1] - x0[1]);
  const Vec3 w = (x1[0] - x0[0]) - (x1[1] - x0[1]);
  const Vec3 n0 = e1.cross(e2), n1 = e1.cross(u2) + u1.cross(e2), n2 = u1.cross(u2);
  k[0] = n0.dot(r);
  k[1] = n0.dot(w) + n1.dot(r);
  k[2] = n1.dot(w) + n2.dot(r);
  k[3] = n2.dot(w);
}

inline Real eval_cubic(const Real k[4], Real t) { return ((k[3] * t + k[2]) * t + k[1]) * t + k[0]; }

// Roots of the cubic in [0, 1], ascending: the interval is split at the critical points into monotone pieces,
// and each piece whose ends differ in sign is bisected. Returns the number of roots (at most 3).
inline int cubic_roots_01(const Real k[4], Real roots[3]) {
  Real cut[4] = {0, 1, 1, 1};
  int cuts = 1;
  // Critical points: 3 k3 t^2 + 2 k2 t + k1 = 0.
  const Real qa = 3 * k[3], qb = 2 * k[2], qc = k[1];
  Real crit[2];
  int nc = 0;
  if (std::abs(qa) > 1e-300) {
    const Real disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      const Real s = std::sqrt(disc);
      crit[nc++] = (-qb - s) / (2 * qa);
      crit[nc++] = (-qb + s) / (2 * qa);
      if (crit[0] > crit[1]) std::swap(crit[0], crit[1]);
    }
  } else if (std::abs(qb) > 1e-300) {
    crit[nc++] = -qc / qb;
  }
  for (int i = 0; i < nc; ++i)
    if (crit[i] > 0 && crit[i] < 1) cut[cuts++] = crit[i];
  cut[cuts] = 1;
  int found = 0;
  for (int i = 0; i < cuts; ++i) {
    Real lo = cut[i], hi = cut[i + 1];
    Real flo = eval_cubic(k, lo), fhi = eval_cubic(k, hi);
    if (flo == 0) { if (found == 0 || roots[found - 1] != lo) roots[found++] = lo; continue; }
    if ((flo < 0) == (fhi < 0) && fhi != 0) continue;
    for (int it = 0; it < 60; ++it) {
      const Real mid = 0.5 * (lo + hi), fm = eval_cubic(k, mid);
      if ((fm < 0) == (flo < 0)) { lo = mid; flo = fm; } else { hi = mid; }
    }
    roots[found++] = hi;
  }
  return found;
}

// Earliest of the candidate times (ascending) at which accept(positions of the four points, moving linearly from
// x0 to x1, at that time) holds. False when there is none.
template <class Accept>
inline bool first_hit(const Vec3 x0[4], const Vec3 x1[4], const Real* times, int n, Real& t_hit, Accept&& accept) {
  for (int i = 0; i < n; ++i) {
    const Real t = times[i];
    Vec3 x[4];
    for (int j = 0; j < 4; ++j) x[j] = (1 - t) * x0[j] + t * x1[j];
    if (accept(x)) {
      t_hit = t;
      return true;
    }
  }
  return false;
}

// Earliest coplanarity root t in [0, 1] of the four points moving linearly from x0 to x1 at which
// accept(positions at t) holds. False when there is none.
template <class Accept>
inline bool first_coplanar_hit(const Vec3 x0[4], const Vec3 x1[4], Real& t_hit, Accept&& accept) {
  Real k[4], roots[3];
  coplanarity_cubic(x0, x1, k);
  return first_hit(x0, x1, roots, cubic_roots_01(k, roots), t_hit, accept);
}

// Earliest time in [0, 1] at which vertex x[0] hits triangle x[1..3] (all moving linearly from x0 to x1), with
// barycentrics accepted within [-delta, 1 + delta], delta = h / longest edge. False when it does not.
// px: the proximity at the hit (barycentrics, normal at that time).
inline bool vertex_triangle_ccd(const Vec3 x0[4], const Vec3 x1[4], Real h, Real& t_hit, TriangleProximity& px) {
  return first_coplanar_hit(x0, x1, t_hit, [&](const Vec3* x) {
    return vertex_triangle_proximity(x[0], x[1], x[2], x[3], h, px) && std::abs(px.d) < h;
  });
}

// True when the four points stay in one plane for the whole step: every coefficient k of their coplanarity cubic
// is rounding noise against the configuration's size L (|k_i| <= 1e-12 L^3; a pair 1e-6 L out of plane gives
// coefficients near 1e-6 L^3). The cubic then says nothing about when the points meet.
inline bool coplanar_throughout(const Vec3 x0[4], const Vec3 x1[4], const Real k[4]) {
  Real size2 = 0;
  for (int j = 1; j < 4; ++j) size2 = std::max({size2, (x0[j] - x0[0]).squaredNorm(), (x1[j] - x1[0]).squaredNorm()});
  const Real bound2 = 1e-24 * size2 * size2 * size2;
  return k[0] * k[0] <= bound2 && k[1] * k[1] <= bound2 && k[2] * k[2] <= bound2 && k[3] * k[3] <= bound2;
}
inline bool coplanar_throughout(const Vec3 x0[4], const Vec3 x1[4]) {
  Real k[4];
  coplanarity_cubic(x0, x1, k);
  return coplanar_throughout(x0, x1, k);
}

// Two edges x[0]x[1] and x[2]x[3] moving within one plane (normal N): from apart, they first meet when an
// endpoint of one reaches the other's line, the roots in [0, 1] of the quadratic N . ((b - a) x (p - a)) for the
// four endpoint-edge pairs (a, b, p moving linearly). Returns those roots, and 0, ascending, in times (at most 9);
// zero roots when the points are collinear (no plane to work in).
inline int coplanar_edge_times(const Vec3 x0[4], const Vec3 x1[4], Real times[9]) {
  int n = 0;
  times[n++] = 0;
  // The plane's normal: the largest cross product of two of the points' differences, at the start or the end.
  Vec3 plane = Vec3::Zero();
  for (const Vec3* x : {x0, x1})
    for (const Vec3& c : {Vec3((x[1] - x[0]).cross(x[3] - x[2])), Vec3((x[1] - x[0]).cross(x[2] - x[0])),
                          Vec3((x[1] - x[0]).cross(x[3] - x[0])), Vec3((x[3] - x[2]).cross(x[0] - x[2]))})
      if (c.squaredNorm() > plane.squaredNorm()) plane = c;
  if (!(plane.squaredNorm() > 0)) return n;
  const int pairs[4][3] = {{0, 1, 2}, {0, 1, 3}, {2, 3, 0}, {2, 3, 1}};  // edge a b, endpoint p of the other
  for (const auto& [a, b, p] : pairs) {
    const Vec3 e0 = x0[b] - x0[a], e1 = (x1[b] - x1[a]) - e0, r0 = x0[p] - x0[a], r1 = (x1[p] - x1[a]) - r0;
    const Real k[4] = {plane.dot(e0.cross(r0)), plane.dot(e0.cross(r1) + e1.cross(r0)), plane.dot(e1.cross(r1)), 0};
    Real roots[3];
    const int found = cubic_roots_01(k, roots);
    for (int i = 0; i < found; ++i) times[n++] = roots[i];
  }
  std::sort(times, times + n);
  return n;
}

// Earliest time in [0, 1] at which edge x[0]x[1] meets edge x[2]x[3] (all moving linearly from x0 to x1): a
// coplanarity root (the same cubic: x[0] against the "triangle" x[1], x[2], x[3]) at which the segments' closest
// points (clamped to the segments) are nearer than tol. px: the closest points at the hit. False when the edges
// stay apart. A pair coplanar throughout the step (a cubic that vanishes everywhere: an edge sliding in the
// plane of another) is tested where an endpoint of one crosses the other's line (coplanar_edge_times).
inline bool edge_edge_ccd(const Vec3 x0[4], const Vec3 x1[4], Real tol, Real& t_hit, EdgeProximity& px) {
  const auto accept = [&](const Vec3* x) { return edge_edge_proximity(x[0], x[1], x[2], x[3], px) && px.d < tol; };
  Real k[4];
  coplanarity_cubic(x0, x1, k);
  if (coplanar_throughout(x0, x1, k)) {
    Real times[9];
    return first_hit(x0, x1, times, coplanar_edge_times(x0, x1, times), t_hit, accept);
  }
  Real roots[3];
  return first_hit(x0, x1, roots, cubic_roots_01(k, roots), t_hit, accept);
}

// The direction along which an edge pair that met at time `when` (closest points px.s, px.t) is sent back: the
// two edges' cross product at the hit, pointed the way the first edge's point lay from the second's at the
// start. When that is no direction of approach -- parallel edges, or a pair that moved within one plane, whose
// cross product is normal to the plane the approach happened in -- the start gap itself. False when neither
// exists (the pair met where it started).
inline bool crossing_normal(const Vec3 x0[4], const Vec3 x1[4], Real when, const EdgeProximity& px, Vec3& n) {
  const Vec3 gap0 = ((1 - px.s) * x0[0] + px.s * x0[1]) - ((1 - px.t) * x0[2] + px.t * x0[3]);
  n = ((1 - when) * (x0[1] - x0[0]) + when * (x1[1] - x1[0]))
          .cross((1 - when) * (x0[3] - x0[2]) + when * (x1[3] - x1[2]));
  if (!(n.squaredNorm() > 1e-20 * gap0.squaredNorm()) || coplanar_throughout(x0, x1)) n = gap0;
  if (!(n.squaredNorm() > 0)) return false;
  n.normalize();
  if (n.dot(gap0) < 0) n = -n;
  return true;
}

}  // namespace clothsim
