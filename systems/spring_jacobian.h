#pragma once
// Analytic Jacobians of the damped Hooke spring of spring_forces.h (Baraff & Witkin 1998 §4.2 and eq. 15-16).
#include "core/math.h"

namespace clothsim {

// Derivatives of the force on particle a of spring a-b: df_a/dx_b = dfdx, df_a/dx_a = -dfdx, and likewise for
// v with dfdv; particle b's blocks are the negatives, so the spring adds [[B, -B], [-B, B]] to a symmetric matrix.
struct SpringJacobian {
  Mat3 dfdx;  // ke [n n^T + max(0, 1 - rest/|d|) (I - n n^T)], N/m
  Mat3 dfdv;  // kd n n^T, N s/m
};

// The transverse term (1 - rest/|d|)(I - n n^T) is negative for a compressed spring and can make
// M - h df/dv - h^2 df/dx indefinite; it is clamped to zero there (Choi & Ko 2002 drop it likewise), so every
// spring's block is positive semi-definite and CG always sees a positive-definite matrix. A compressed spring
// is then linearised as if straight; the force itself (spring_force) is exact, only its Jacobian is clamped.
// The x-derivative of the damping force (non-symmetric, zero when the relative velocity is along the spring) is
// left out, as Baraff & Witkin suggest.
inline SpringJacobian spring_jacobian(const Vec3& xa, const Vec3& xb, Real rest, Real ke, Real kd) {
  const Vec3 d = xb - xa;
  const Real len = d.norm();
  if (!(len > 0)) return {Mat3::Zero(), Mat3::Zero()};
  const Vec3 n = d / len;
  const Mat3 nn = n * n.transpose();
  const Real transverse = len > rest ? 1 - rest / len : 0;
  return {ke * (nn + transverse * (Mat3::Identity() - nn)), kd * nn};
}

// dfdx w without forming the matrix: ke [t w + (1 - t) (n.w) n], t the clamped transverse factor above. The
// right-hand side's (df/dx) v needs only this product, twice per spring (once from each end): about a third of
// the operations of spring_jacobian, which also forms n n^T and dfdv.
inline Vec3 spring_dfdx_times(const Vec3& xa, const Vec3& xb, Real rest, Real ke, const Vec3& w) {
  const Vec3 d = xb - xa;
  const Real len = d.norm();
  if (!(len > 0)) return Vec3::Zero();
  const Vec3 n = d / len;
  const Real transverse = len > rest ? 1 - rest / len : 0;
  return ke * (transverse * w + ((1 - transverse) * n.dot(w)) * n);
}

// The spring's block of the backward-Euler matrix A = M - h df/dv - h^2 df/dx: h dfdv + h^2 dfdx.
inline Mat3 spring_system_block(const SpringJacobian& j, Real h) { return h * j.dfdv + (h * h) * j.dfdx; }

}  // namespace clothsim
