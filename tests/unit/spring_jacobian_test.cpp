#include <cmath>
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <utility>

#include "systems/spring_forces.h"
#include "systems/spring_jacobian.h"

using namespace clothsim;

namespace {

// Central differences of the force on particle a with respect to particle b's position (or velocity).
Mat3 finite_difference(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb, Real rest, Real ke, Real kd,
                       bool wrt_velocity) {
  const Real eps = 1e-6;
  Mat3 j;
  for (int c = 0; c < 3; ++c) {
    Vec3 e = Vec3::Zero();
    e[c] = eps;
    const Vec3 plus = wrt_velocity ? spring_force(xa, xb, va, vb + e, rest, ke, kd)
                                   : spring_force(xa, xb + e, va, vb, rest, ke, kd);
    const Vec3 minus = wrt_velocity ? spring_force(xa, xb, va, vb - e, rest, ke, kd)
                                    : spring_force(xa, xb - e, va, vb, rest, ke, kd);
    j.col(c) = (plus - minus) / (2 * eps);
  }
  return j;
}

}  // namespace

TEST_CASE("spring Jacobian matches finite differences of the spring force for a stretched spring") {
  const Vec3 xa(0.1, -0.2, 0.3), xb(0.9, 0.4, -0.2);  // length 1.114, rest 0.8: strain 39%
  const Real rest = 0.8, ke = 250, kd = 1.5;
  const SpringJacobian j = spring_jacobian(xa, xb, rest, ke, kd);
  // Position derivative at zero relative velocity: the damping force's x-derivative (left out) vanishes there.
  const Mat3 fd_x = finite_difference(xa, xb, Vec3::Zero(), Vec3::Zero(), rest, ke, kd, false);
  CHECK((j.dfdx - fd_x).norm() < 1e-6 * ke);
  // The velocity derivative is exact for any velocities.
  const Mat3 fd_v = finite_difference(xa, xb, Vec3(0.3, 1, -2), Vec3(-1, 0.5, 0.7), rest, ke, kd, true);
  CHECK((j.dfdv - fd_v).norm() < 1e-7);
  // Newton's third law: the force on b is -f_a, so d f_a/d x_a = -dfdx (translation invariance).
  const Real eps = 1e-6;
  const Vec3 e(eps, 0, 0);
  const Vec3 dfa_dxa = (spring_force(xa + e, xb, Vec3::Zero(), Vec3::Zero(), rest, ke, kd) -
                        spring_force(xa - e, xb, Vec3::Zero(), Vec3::Zero(), rest, ke, kd)) / (2 * eps);
  CHECK((dfa_dxa + j.dfdx.col(0)).norm() < 1e-6 * ke);
}

TEST_CASE("compressed spring: the transverse term is clamped so the block stays positive semi-definite") {
  const Vec3 xa(0, 0, 0), xb(0.3, 0.4, 0);  // length 0.5, rest 1: compressed to half
  const Real rest = 1, ke = 100;
  const SpringJacobian j = spring_jacobian(xa, xb, rest, ke, 0);
  // The exact Jacobian has transverse eigenvalue ke (1 - rest/len) = -100 (twice) and ke along the spring.
  const Mat3 exact = finite_difference(xa, xb, Vec3::Zero(), Vec3::Zero(), rest, ke, 0, false);
  Eigen::SelfAdjointEigenSolver<Mat3> exact_eig(0.5 * (exact + exact.transpose()));
  CHECK(exact_eig.eigenvalues()[0] == doctest::Approx(-100).epsilon(1e-6));
  // The clamped one keeps only ke n n^T: eigenvalues 0, 0, ke.
  Eigen::SelfAdjointEigenSolver<Mat3> eig(j.dfdx);
  CHECK(eig.eigenvalues()[0] == doctest::Approx(0).scale(1));
  CHECK(eig.eigenvalues()[1] == doctest::Approx(0).scale(1));
  CHECK(eig.eigenvalues()[2] == doctest::Approx(ke));
  const Vec3 n = (xb - xa).normalized();
  CHECK((j.dfdx * n - ke * n).norm() < 1e-12);
  // The system block h kd n n^T + h^2 dfdx of a stretched spring is symmetric positive semi-definite too.
  const Mat3 b = spring_system_block(spring_jacobian(xa, Vec3(1.2, 1.6, 0), rest, ke, 2), 0.01);
  CHECK((b - b.transpose()).norm() < 1e-15);
  CHECK(Eigen::SelfAdjointEigenSolver<Mat3>(b).eigenvalues()[0] >= 0);
}

TEST_CASE("a spring's system block is exactly symmetric, so its six stored entries apply as the whole block") {
  // The implicit step keeps each spring's six entries (core/math.h); that is only the same matrix when the
  // block is symmetric to the last bit, which n n^T and I - n n^T are (n_i n_j = n_j n_i in floating point).
  const SpringJacobian j = spring_jacobian(Vec3(0.1, -0.2, 0.3), Vec3(1.3, 0.4, -0.7), 0.9, 250, 1.5);
  const Mat3 block = spring_system_block(j, 0.02);
  CHECK(block == block.transpose());
  const Sym3 stored = Sym3::from(block);
  CHECK(stored.full() == block);
  const Vec3 p(0.7, -1.9, 2.3);
  CHECK((stored * p - block * p).norm() <= 1e-15 * (block * p).norm());
  CHECK((block * p).norm() > 0.05);  // a block that does something
  // Kept in float (Sym3f, as the CG's products read it), each entry is within float's unit roundoff, 2^-24, of the
  // double: the product errs by at most that times |B| |p| (Cauchy-Schwarz per row), and by more than 2^-40 here.
  const Sym3f kept = Sym3f::from(block);
  const double err = (kept * p - block * p).norm(), bound = std::ldexp(1.0, -24) * block.norm() * p.norm();
  CHECK(err <= bound);
  CHECK(err > std::ldexp(1.0, -40) * block.norm() * p.norm());
}

TEST_CASE("dfdx applied to a vector without the matrix equals the Jacobian's product, stretched and compressed") {
  const Vec3 w(0.7, -1.9, 2.3);
  const std::pair<Vec3, Real> cases[] = {{Vec3(1.3, 0.4, -0.7), 0.9},   // stretched 54%: transverse term on
                                         {Vec3(0.3, 0.4, 0.0), 1.0},    // compressed: clamped to n n^T
                                         {Vec3(0.0, 0.0, 0.0), 1.0}};   // zero length: nothing
  const Vec3 xa(0.1, -0.2, 0.3);
  for (const auto& [d, rest] : cases) {
    const Vec3 xb = xa + d;
    const Vec3 matrix = spring_jacobian(xa, xb, rest, 250, 1.5).dfdx * w;
    const Vec3 direct = spring_dfdx_times(xa, xb, rest, 250, w);
    CHECK((direct - matrix).norm() <= 1e-13 * std::max(1.0, matrix.norm()));
  }
  CHECK(spring_dfdx_times(xa, xa + Vec3(1.3, 0.4, -0.7), 0.9, 250, w).norm() > 100);  // it does something
}
