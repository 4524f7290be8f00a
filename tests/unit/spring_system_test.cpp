// The closed-form problems of the studies: a chain built without a mesh has the highest frequency the
// discrete-string formula gives (checked by a dense eigen-solve of the stiffness the force kernel produces),
// and the spring energy is k d^2 / 2.
#include <doctest/doctest.h>

// GCC 12 warns inside Eigen's AVX-512 eigen-solver code (a false positive in a system header).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/spring_system.h"
#include "systems/energy.h"
#include "systems/forces.h"

using namespace clothsim;

namespace {

SpringSystemDesc chain_desc(int n, Real k, Real m) {
  SpringSystemDesc d;
  for (int i = 0; i <= n + 1; ++i) {
    d.positions.push_back(Vec3(0.1 * i, 0, 0));
    d.masses.push_back(i == 0 || i == n + 1 ? 0.0 : m);
    if (i > 0) { d.spring_a.push_back(i - 1); d.spring_b.push_back(i); }
  }
  d.stiffness = k;
  return d;
}

}  // namespace

TEST_CASE("spring system: the chain's highest frequency matches 2 sqrt(k/m) sin(n pi / (2 (n + 1)))") {
  const int n = 8;
  const Real k = 250, m = 0.01;
  BuiltScene b = build_spring_system(chain_desc(n, k, m));
  CHECK(b.model.pinned == std::vector<Index>{0, n + 1});
  CHECK(b.model.spring_count == n + 1);
  // Axial stiffness matrix of the free masses by central differences of the accelerations (exact up to
  // round-off: the force is linear along the axis), then its eigenvalues w^2.
  Workspace ws = make_workspace(b.model, b.options);
  Eigen::MatrixXd a(n, n);
  const Real du = 1e-6;
  for (int j = 0; j < n; ++j) {
    std::vector<Vec3> x = b.state.x;
    x[j + 1].x() += du;
    eval_forces(b.model, x, b.state.v, 0, ws);
    std::vector<Vec3> plus = ws.f;
    x[j + 1].x() -= 2 * du;
    eval_forces(b.model, x, b.state.v, 0, ws);
    for (int i = 0; i < n; ++i) a(i, j) = -(plus[i + 1].x() - ws.f[i + 1].x()) / (2 * du);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (a + a.transpose()));
  const Real w_max = std::sqrt(eig.eigenvalues().maxCoeff());
  CHECK(w_max == doctest::Approx(2 * std::sqrt(k / m) * std::sin(n * std::numbers::pi / (2.0 * (n + 1)))).epsilon(1e-6));
}

TEST_CASE("spring system: spring energy is k d^2 / 2 and bad springs are errors") {
  BuiltScene b = build_spring_system(chain_desc(1, 40, 0.5));
  b.state.x[1].x() += 0.01;  // one spring stretched, the other compressed, by 1 cm
  CHECK(spring_potential_energy(b.model, b.state.x) == doctest::Approx(2 * 0.5 * 40 * 0.01 * 0.01));
  SpringSystemDesc bad = chain_desc(1, 40, 0.5);
  bad.spring_b[0] = 7;
  CHECK_THROWS_AS(build_spring_system(bad), Error);
  bad = chain_desc(1, 40, 0.5);
  bad.masses.pop_back();
  CHECK_THROWS_AS(build_spring_system(bad), Error);
}
