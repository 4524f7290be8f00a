// The Cholesky factor of a matrix of unconnected pieces (core/cholesky_factor.h): one factor a connected piece,
// small pieces gathered, the longest first; its solve checked by an independent product, and the implicit run
// byte-identical whether the pieces factor one after the other or at once.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "core/blas_kernel.h"
#include "core/build_model.h"
#include "core/cholesky_factor.h"
#include "systems/step.h"
#include "tests/support/block_laplacian.h"
#include "tests/support/scene_fixtures.h"
#include "tests/support/spring_fixtures.h"

using namespace clothsim;
using namespace clothsim::test;

namespace {

// Grid sheets of the given sizes side by side in one scene, 1 m apart: one cloth each, so one piece each.
BuiltScene sheets(const std::vector<int>& sizes, Integrator integrator = Integrator::implicit) {
  SceneDesc scene = grid_scene(sizes[0], sizes[0], 0.5, integrator);
  scene.cloths.clear();
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    ClothDesc c;
    c.name = "sheet" + std::to_string(k);
    c.grid_nx = c.grid_ny = sizes[k];
    c.grid_w = c.grid_h = 0.5;
    c.stiffness = 1e4;
    c.damping = 0.1;
    c.pins = {0, Index(sizes[k] - 1)};
    c.transform.rotate = Vec3(90, 0, 0);
    c.transform.translate = Vec3(Real(k), 0, 0);
    scene.cloths.push_back(c);
  }
  scene.simulation.cg_tolerance = 1e-6;
  BuiltScene s = build(scene);
  s.options.solver.preconditioner = Preconditioner::cholesky;
  return s;
}

}  // namespace

TEST_CASE("the Cholesky factor: one factor a piece, small pieces gathered, the most flops first") {
  // 32^2 = 1,024 and 24^2 = 576 particles are pieces of their own; two 8^2 = 64 sheets are gathered into one
  // group, which would take more until it held 512 particles.
  const BuiltScene all = sheets({24, 8, 32, 8});
  const CholeskyFactorPtr f = build_cholesky_factor(all.model);
  REQUIRE(cholesky_piece_count(*f) == 3);
  // Each piece's analysis is that of its sheet alone (the ordering sees the same graph in the same numbering),
  // so the flops are those of three separate factors, largest first.
  const double big = cholesky_flops(*build_cholesky_factor(sheets({32}).model));
  const double mid = cholesky_flops(*build_cholesky_factor(sheets({24}).model));
  const double small = cholesky_flops(*build_cholesky_factor(sheets({8, 8}).model));
  REQUIRE(cholesky_piece_count(*build_cholesky_factor(sheets({8, 8}).model)) == 1);
  CHECK(cholesky_piece_flops(*f, 0) == big);
  CHECK(cholesky_piece_flops(*f, 1) == mid);
  CHECK(cholesky_piece_flops(*f, 2) == small);
  CHECK(cholesky_flops(*f) == doctest::Approx(big + mid + small).epsilon(1e-12));
  CHECK(small > 0);
  CHECK(mid > 2 * small);
  CHECK(big > 2 * mid);
}

TEST_CASE("the Cholesky factor of unconnected pieces solves a block Laplacian, checked by an independent product") {
  const BuiltScene all = sheets({24, 8, 32, 8});
  const Model& m = all.model;
  const BlockLaplacian a = block_laplacian(m);
  CholeskyFactorPtr f = build_cholesky_factor(m);
  REQUIRE(cholesky_piece_count(*f) == 3);
  set_block_laplacian(m, a, *f);
  REQUIRE(cholesky_factorize(*f));
  std::vector<Vec3> r, z(std::size_t(m.particle_count), Vec3::Zero());
  for (Index i = 0; i < m.particle_count; ++i) r.emplace_back(std::sin(Real(i)), 1, Real(i % 7) - 3);
  cholesky_solve(*f, r.data(), z.data());
  CHECK(block_laplacian_residual(m, a, z, r) < 1e-10);
}

TEST_CASE("an implicit run of unconnected pieces is byte-identical at 1 and 2 threads, the pieces factored at once") {
  // Where the BLAS takes calls at once (a threaded OpenBLAS, as tools/setup installs), the two threads factor
  // the two pieces together; elsewhere one after the other. The bytes must not tell which.
  INFO("BLAS calls may overlap: " << blas_calls_may_overlap());
  State runs[2];
  for (int t = 1; t <= 2; ++t) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
    BuiltScene s = sheets({24, 24});
    Workspace ws = make_workspace(s.model, s.options);
    run_steps(s.model, s.options, s.state, ws, 1.0 / 60, 12);
    CHECK(ws.cholesky_h == 1.0 / 60);  // the last factorisation succeeded: no block-Jacobi fallback
    runs[t - 1] = s.state;
  }
  REQUIRE(runs[0].x.size() == runs[1].x.size());
  CHECK(std::memcmp(runs[0].x.data(), runs[1].x.data(), runs[0].x.size() * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(runs[0].v.data(), runs[1].v.data(), runs[0].v.size() * sizeof(Vec3)) == 0);
}
