#pragma once
// Continuous vertex-triangle detection along the linear trajectories of a step (Provot 1997; Bridson, Fedkiw &
// Anderson 2002 §6.2): the times t in [0, 1] at which the vertex and the triangle are coplanar are the roots of
// the cubic ((b - a) x (c - a)) . (p - a) = 0; a root whose point lies inside the triangle is a collision.
// Edge-edge detection (§4 of the same paper) solves the same cubic for the four edge endpoints; a root at which the
// closest points of the two segments come within a tolerance is a collision.
#include <cmath>

#include "systems/proximity.h"

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

// Earliest coplanarity root t in [0, 1] of the four points moving linearly from x0 to x1 at which
// accept(positions at t) holds. False when there is none.
template <class Accept>
inline bool first_coplanar_hit(const Vec3 x0[4], const Vec3 x1[4], Real& t_hit, Accept&& accept) {
  Real k[4], roots[3];
  coplanarity_cubic(x0, x1, k);
  const int n = cubic_roots_01(k, roots);
  for (int i = 0; i < n; ++i) {
    const Real t = roots[i];
    Vec3 x[4];
    for (int j = 0; j < 4; ++j) x[j] = (1 - t) * x0[j] + t * x1[j];
    if (accept(x)) {
      t_hit = t;
      return true;
    }
  }
  return false;
}

// Earliest time in [0, 1] at which vertex x[0] hits triangle x[1..3] (all moving linearly from x0 to x1), with
// barycentrics accepted within [-delta, 1 + delta], delta = h / longest edge. False when it does not.
// px: the proximity at the hit (barycentrics, normal at that time).
inline bool vertex_triangle_ccd(const Vec3 x0[4], const Vec3 x1[4], Real h, Real& t_hit, TriangleProximity& px) {
  return first_coplanar_hit(x0, x1, t_hit, [&](const Vec3* x) {
    return vertex_triangle_proximity(x[0], x[1], x[2], x[3], h, px) && std::abs(px.d) < h;
  });
}

// Earliest time in [0, 1] at which edge x[0]x[1] meets edge x[2]x[3] (all moving linearly from x0 to x1): a
// coplanarity root (the same cubic: x[0] against the "triangle" x[1], x[2], x[3]) at which the segments' closest
// points (clamped to the segments) are nearer than tol. px: the closest points at the hit. False when the edges
// stay apart. A pair coplanar throughout the step (a cubic that is zero everywhere) is tested at t = 0 only.
inline bool edge_edge_ccd(const Vec3 x0[4], const Vec3 x1[4], Real tol, Real& t_hit, EdgeProximity& px) {
  return first_coplanar_hit(x0, x1, t_hit, [&](const Vec3* x) {
    return edge_edge_proximity(x[0], x[1], x[2], x[3], px) && px.d < tol;
  });
}

}  // namespace clothsim
