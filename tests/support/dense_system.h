#pragma once
// The dense reference of the implicit step's linear system, for the solver tests (integrate_implicit, multigrid).
// GCC 12 with -march=native reports a false -Wmaybe-uninitialized inside Eigen's AVX-512 GEMM packing for the
// dense products of the files that include this; it is Eigen's internals, not this code.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#include <tuple>
#include <utility>

#include "core/model.h"
#include "systems/spring_forces.h"
#include "systems/spring_jacobian.h"

namespace clothsim::test {

// Dense reference system of one step (Baraff & Witkin eq. 15-16): A = M - h df/dv - h^2 df/dx,
// b = h (f + h df/dx v), with the rows and columns of pinned particles replaced by the identity and b = 0 there.
inline std::pair<Eigen::MatrixXd, Eigen::VectorXd> dense_system(const Model& m, const State& st, Real h) {
  const Index n = m.particle_count;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * n, 3 * n), D = K;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * n), v(3 * n), mass = f;
  for (Index i = 0; i < n; ++i) {
    v.segment<3>(3 * i) = st.v[i];
    if (m.particle_inv_mass[i] > 0) {
      mass.segment<3>(3 * i).setConstant(1 / m.particle_inv_mass[i]);
      f.segment<3>(3 * i) += m.gravity / m.particle_inv_mass[i];
    }
  }
  for (Index k = 0; k < m.spring_count; ++k) {
    const Index a = m.spring_a[k], b = m.spring_b[k];
    const SpringJacobian j = spring_jacobian(st.x[a], st.x[b], m.spring_rest[k], m.spring_ke[k], m.spring_kd[k]);
    const Vec3 fa = spring_force(st.x[a], st.x[b], st.v[a], st.v[b], m.spring_rest[k], m.spring_ke[k], m.spring_kd[k]);
    f.segment<3>(3 * a) += fa;
    f.segment<3>(3 * b) -= fa;
    for (auto [p, q, sign] : {std::tuple{a, a, -1.0}, {b, b, -1.0}, {a, b, 1.0}, {b, a, 1.0}}) {
      K.block<3, 3>(3 * p, 3 * q) += sign * j.dfdx;
      D.block<3, 3>(3 * p, 3 * q) += sign * j.dfdv;
    }
  }
  Eigen::MatrixXd A = Eigen::MatrixXd(mass.asDiagonal()) - h * D - h * h * K;
  Eigen::VectorXd rhs = h * (f + h * K * v);
  for (Index p : m.pinned) {
    A.middleRows(3 * p, 3).setZero();
    A.middleCols(3 * p, 3).setZero();
    A.block<3, 3>(3 * p, 3 * p).setIdentity();
    rhs.segment<3>(3 * p).setZero();
  }
  return {A, rhs};
}

}  // namespace clothsim::test
