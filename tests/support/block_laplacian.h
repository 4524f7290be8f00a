#pragma once
// A matrix to test the Cholesky factor (core/cholesky_factor.h) against: a shifted graph Laplacian with 3x3 blocks
// over a model's springs. Each spring couples its ends by -(I + 0.1 u u^T) for a fixed per-spring direction u,
// and each diagonal block is its springs' sum plus the identity, so the matrix is symmetric positive definite
// whatever the ordering. Its product, applied block by block, checks a solve independently of the factor.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/cholesky_factor.h"
#include "core/model.h"

namespace clothsim::test {

struct BlockLaplacian {
  std::vector<Sym3> spring;
  std::vector<Mat3> diagonal;
};

inline BlockLaplacian block_laplacian(const Model& m) {
  BlockLaplacian a;
  a.diagonal.assign(std::size_t(m.particle_count), Mat3::Identity());
  for (Index s = 0; s < m.spring_count; ++s) {
    const Vec3 u = Vec3(1, std::sin(Real(s)), std::cos(Real(3 * s))).normalized();
    const Mat3 b = Mat3::Identity() + 0.1 * u * u.transpose();
    a.spring.push_back(Sym3::from(b));
    a.diagonal[std::size_t(m.spring_a[s])] += b;
    a.diagonal[std::size_t(m.spring_b[s])] += b;
  }
  return a;
}

// The matrix's values set into the factor (cleared first).
inline void set_block_laplacian(const Model& m, const BlockLaplacian& a, CholeskyFactor& f) {
  cholesky_clear(f);
  for (Index i = 0; i < m.particle_count; ++i) cholesky_add_diagonal(f, i, Sym3::from(a.diagonal[std::size_t(i)]));
  for (Index s = 0; s < m.spring_count; ++s)
    cholesky_add_coupling(f, s, a.spring[std::size_t(s)], m.spring_a[s], m.spring_b[s]);
}

// The largest |A z - r| over the particles, with A applied block by block.
inline Real block_laplacian_residual(const Model& m, const BlockLaplacian& a, const std::vector<Vec3>& z,
                                     const std::vector<Vec3>& r) {
  std::vector<Vec3> az(r.size());
  for (Index i = 0; i < m.particle_count; ++i) az[std::size_t(i)] = a.diagonal[std::size_t(i)] * z[std::size_t(i)];
  for (Index s = 0; s < m.spring_count; ++s) {
    const Mat3 b = a.spring[std::size_t(s)].full();
    az[std::size_t(m.spring_a[s])] -= b * z[std::size_t(m.spring_b[s])];
    az[std::size_t(m.spring_b[s])] -= b * z[std::size_t(m.spring_a[s])];
  }
  Real worst = 0;
  for (std::size_t i = 0; i < r.size(); ++i) worst = std::max(worst, (az[i] - r[i]).norm());
  return worst;
}

}  // namespace clothsim::test
