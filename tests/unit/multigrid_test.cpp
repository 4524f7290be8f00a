#include <cmath>
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <cstring>

#include "systems/integrate_implicit.h"
#include "systems/multigrid.h"
#include "tests/support/dense_system.h"
#include "tests/support/spring_fixtures.h"

using namespace clothsim;
using namespace clothsim::test;

namespace {

// A small hanging sheet, stretched, bent out of plane and moving, so every spring block has its transverse and
// damping parts; implicit with the multigrid preconditioner on levels down to `coarsest` nodes.
struct SmallSheet {
  BuiltScene s;
  Workspace ws;
  Real h = 0.02;
};

SmallSheet small_sheet(int nx, int ny, Index coarsest) {
  GridSpec g;
  g.nx = nx;
  g.ny = ny;
  g.damping = 0.3;
  g.bend_scale = 0.3;
  g.pins = {0, nx - 1};
  g.integrator = Integrator::implicit;
  SmallSheet sh{grid_sheet(g), {}};
  Model& m = sh.s.model;
  sh.s.options.solver.preconditioner = Preconditioner::multigrid;
  sh.s.options.solver.cg_tolerance = 1e-12;
  for (Index i = 0; i < m.particle_count; ++i) {
    sh.s.state.x[i] *= 1.15;
    sh.s.state.x[i].z() += 0.02 * std::sin(1.7 * i);
    if (m.particle_inv_mass[i] > 0) sh.s.state.v[i] = Vec3(std::sin(0.3 * i), std::cos(0.7 * i), 0.5 * std::sin(i));
  }
  sh.ws = make_workspace(m, sh.s.options);
  sh.ws.multigrid = build_multigrid_levels(m, coarsest);
  // One step builds the spring blocks, the block-Jacobi inverses and every level's operator at the state above.
  State out = sh.s.state;
  step(m, sh.s.options, sh.s.state, out, sh.ws, sh.h);
  return sh;
}

// A level's operator as a dense matrix, as the cycle applies it: D_I on the diagonal, -B of each edge in the rows
// of both its ends.
Eigen::MatrixXd level_matrix(const MultigridLevel& L) {
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 * L.node_count, 3 * L.node_count);
  for (Index n = 0; n < L.node_count; ++n) {
    a.block<3, 3>(3 * n, 3 * n) = L.diag[n].full();
    for (Index k = L.row_offset[n]; k < L.row_offset[n + 1]; ++k)
      a.block<3, 3>(3 * n, 3 * L.row_col[k]) = -L.edge_block[L.row_edge[k]].full();
  }
  return a;
}

// The piecewise-constant prolongation of a level: a 3x3 identity at (member, aggregate); zero rows for pinned.
Eigen::MatrixXd prolongation(const MultigridLevel& L) {
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(3 * Index(L.parent.size()), 3 * L.node_count);
  for (Index i = 0; i < Index(L.parent.size()); ++i)
    if (L.parent[i] >= 0) p.block<3, 3>(3 * i, 3 * L.parent[i]).setIdentity();
  return p;
}

// The cycle B applied to the columns of the identity (zero rows and columns at pinned particles).
Eigen::MatrixXd dense_cycle(SmallSheet& sh) {
  const Model& m = sh.s.model;
  const Index n = m.particle_count;
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  std::vector<Vec3> r(n, Vec3::Zero()), z(n);
  for (Index i = 0; i < n; ++i) {
    if (!(m.particle_inv_mass[i] > 0)) continue;
    for (int c = 0; c < 3; ++c) {
      r[i][c] = 1;
      apply_multigrid(m, sh.s.state.x, sh.h, ImplicitLayout::spring_blocks, sh.ws, r, z);
      r[i][c] = 0;
      for (Index k = 0; k < n; ++k) b.block<3, 1>(3 * k, 3 * i + c) = z[k];
    }
  }
  return b;
}

// The peer sheet of docs/performance.md at side x side (1 m, 1 kg, two corners pinned, 10000 N/m, 1/48 s).
BuiltScene peer_sheet(int side, Preconditioner preconditioner, Real cg_tolerance) {
  SceneDesc scene = grid_scene(side, side, 1.0, Integrator::implicit, 1.0 / 48);
  scene.simulation.cg_tolerance = cg_tolerance;
  scene.simulation.preconditioner = preconditioner;
  scene.forces.air_damping = 0.1;
  ClothDesc& c = scene.cloths[0];
  c.density = 1;
  c.stiffness = 10000;
  c.bend_scale = 0.1;
  c.damping = 0.1;
  c.pins = {0, side - 1};
  return build(scene);
}

}  // namespace

TEST_CASE("each level's operator is P^T A P of the level above, formed densely") {
  SmallSheet sh = small_sheet(9, 7, 2);
  const Model& m = sh.s.model;
  REQUIRE(sh.ws.multigrid.levels.size() >= 3);
  // The filtered A: dense_system puts an identity on pinned rows, which the zero rows of P leave out.
  Eigen::MatrixXd a = dense_system(m, sh.s.state, sh.h).first;
  Eigen::MatrixXd p = Eigen::MatrixXd::Identity(a.rows(), a.cols());
  for (const MultigridLevel& L : sh.ws.multigrid.levels) {
    p = p * prolongation(L);
    const Eigen::MatrixXd galerkin = p.transpose() * a * p;
    const Eigen::MatrixXd ours = level_matrix(L);
    MESSAGE("level of " << L.node_count << " nodes: |ours - P^T A P| = " << (ours - galerkin).norm() << " of "
                        << galerkin.norm());
    // The springs' and each level's edge blocks are kept in float (core/math.h), each off by at most 2^-24 of
    // itself, so a level is P^T A P to about that (2.1e-8 of its norm here); a wrong sum would be off by a block.
    CHECK((ours - galerkin).norm() <= std::ldexp(1.0, -22) * galerkin.norm());
    for (Index n = 0; n < L.node_count; ++n)
      CHECK((L.diag_inv[n].full() * L.diag[n].full() - Mat3::Identity()).norm() < 1e-12);
  }
  // The coarsest level is factored exactly.
  const MultigridLevel& last = sh.ws.multigrid.levels.back();
  CHECK((sh.ws.multigrid.dense - level_matrix(last)).norm() <= 1e-14 * sh.ws.multigrid.dense.norm());
}

TEST_CASE("the multigrid cycle is a symmetric positive definite preconditioner with B A's spectrum in (0, 2)") {
  SmallSheet sh = small_sheet(9, 7, 2);
  const Model& m = sh.s.model;
  const Eigen::MatrixXd b = dense_cycle(sh);
  const Eigen::MatrixXd a = dense_system(m, sh.s.state, sh.h).first;
  // Symmetric to round-off: u . B v = v . B u for every pair of unit vectors.
  CHECK((b - b.transpose()).norm() <= 1e-13 * b.norm());
  // Restricted to the free particles (pinned rows and columns are zero in B and an identity in A's dense form).
  std::vector<Index> free;
  for (Index i = 0; i < m.particle_count; ++i)
    if (m.particle_inv_mass[i] > 0)
      for (int c = 0; c < 3; ++c) free.push_back(3 * i + c);
  const Index f = Index(free.size());
  Eigen::MatrixXd bf(f, f), af(f, f);
  for (Index r = 0; r < f; ++r)
    for (Index c = 0; c < f; ++c) {
      bf(r, c) = 0.5 * (b(free[r], free[c]) + b(free[c], free[r]));
      af(r, c) = a(free[r], free[c]);
    }
  const Eigen::VectorXd eig_b = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(bf).eigenvalues();
  CHECK(eig_b.minCoeff() > 0);
  // B A is similar to A^1/2 B A^1/2: real eigenvalues 1 - (those of the cycle's error propagation E), in (0, 2)
  // when |E|_A < 1 (above 1 where the over-corrected coarse step overshoots). Their spread is the condition
  // number CG sees, against block-Jacobi's (D^-1 A, D the 3x3 diagonal blocks).
  const Eigen::VectorXd eig_ba = Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>(af, bf.inverse()).eigenvalues();
  Eigen::MatrixXd df = Eigen::MatrixXd::Zero(f, f);
  for (Index r = 0; r < f; r += 3) df.block<3, 3>(r, r) = af.block<3, 3>(r, r);
  const Eigen::VectorXd eig_da = Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>(af, df).eigenvalues();
  const Real kappa = eig_ba.maxCoeff() / eig_ba.minCoeff(), kappa_jacobi = eig_da.maxCoeff() / eig_da.minCoeff();
  MESSAGE("eigenvalues of B A: " << eig_ba.minCoeff() << " to " << eig_ba.maxCoeff() << " (condition " << kappa
                                 << "); block-Jacobi's: " << eig_da.minCoeff() << " to " << eig_da.maxCoeff()
                                 << " (condition " << kappa_jacobi << ")");
  CHECK(eig_ba.minCoeff() > 0.2);
  CHECK(eig_ba.maxCoeff() < 2);
  CHECK(kappa < 5);
  CHECK(kappa * 10 < kappa_jacobi);
}

TEST_CASE("multigrid CG takes far fewer iterations than block-Jacobi on a 64 x 64 hanging sheet, same answer") {
  auto run = [](Preconditioner pc, std::vector<int>& iterations) {
    BuiltScene s = peer_sheet(64, pc, 1e-6);
    Workspace ws = make_workspace(s.model, s.options);
    State scratch = s.state;
    for (int k = 0; k < 6; ++k) {
      iterations.push_back(step(s.model, s.options, s.state, scratch, ws, s.options.dt).solve.cg_iterations);
      std::swap(s.state, scratch);
    }
    return s.state;
  };
  std::vector<int> jacobi, multigrid;
  const State sj = run(Preconditioner::jacobi, jacobi);
  const State sm = run(Preconditioner::multigrid, multigrid);
  std::string listed;
  for (std::size_t k = 0; k < jacobi.size(); ++k)
    listed += " " + std::to_string(jacobi[k]) + "/" + std::to_string(multigrid[k]);
  MESSAGE("CG iterations per step, block-Jacobi / multigrid:" << listed);
  // The first step from the flat sheet at rest is one iteration for both (gravity is normal to every spring).
  CHECK(jacobi[0] == 1);
  CHECK(multigrid[0] == 1);
  for (std::size_t k = 1; k < jacobi.size(); ++k) CHECK(multigrid[k] * 8 < jacobi[k]);
  // Both solved every step to |r| <= 1e-6 |b|: the sheets agree far within their motion (it fell about 0.1 m).
  Real worst = 0, fall = 0;
  for (std::size_t i = 0; i < sj.x.size(); ++i) {
    worst = std::max(worst, (sj.x[i] - sm.x[i]).norm());
    fall = std::max(fall, std::abs(sj.v[i].y()));
  }
  MESSAGE("largest position difference " << worst << " m; largest vertical speed " << fall << " m/s");
  CHECK(worst < 1e-4);
  CHECK(fall > 0.5);
}

TEST_CASE("multigrid: the same bytes at 1, 2 and 3 threads") {
  // 72 x 72 = 5184 particles: three blocks of the particle grain on the finest level, two on the first coarse one.
  auto run = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    BuiltScene s = peer_sheet(72, Preconditioner::multigrid, 1e-2);
    Workspace ws = make_workspace(s.model, s.options);
    run_steps(s.model, s.options, s.state, ws, s.options.dt, 6);
    return s.state;
  };
  const State one = run(1), two = run(2), three = run(3);
  auto same = [](const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
    return p.size() == q.size() && std::memcmp(p.data(), q.data(), p.size() * sizeof(Vec3)) == 0;
  };
  CHECK(same(one.x, two.x));
  CHECK(same(one.v, two.v));
  CHECK(same(one.x, three.x));
  CHECK(same(one.v, three.v));
}
