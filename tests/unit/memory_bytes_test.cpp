// What a run holds for its whole length, counted from the arrays' sizes against a hand count of a grid sheet's
// elements (docs/performance.md, "Memory and loading": at most 400 bytes a particle on the 1024^2 sheet). The RSS
// a run reports (--stats peak_rss_bytes) is this plus the program image and the build's transient peak; this
// test guards the part that scales with the mesh, without timing or measuring the process.
#include <doctest/doctest.h>

#include <cmath>

#include "core/csr.h"
#include "core/memory_bytes.h"
#include "core/multigrid_levels.h"
#include "core/spring_chunks.h"
#include "systems/step.h"
#include "tests/support/scene_fixtures.h"
#include "tests/support/sheet_scene.h"

using namespace clothsim;

namespace {

struct GridCounts {
  double particles, springs, triangles;
};

// An n x n grid: Provot's structural, shear and flex springs; two triangles a cell.
GridCounts grid_counts(double n) {
  return {n * n, 2 * n * (n - 1) + 2 * (n - 1) * (n - 1) + 2 * n * (n - 2), 2 * (n - 1) * (n - 1)};
}

// Hand count of a symplectic grid model with uniform parameters, blocked layout, one chunk and one pass:
// inverse mass (8 a particle), spring a, b (4 each) and rest (8), triangle corners (3 x 4) and the triangle CSR
// (offset 4 a particle + 1, 3 x 4 a triangle), UVs (16 a particle, their indices equal the vertex indices and are
// not stored), five uniform fields of one scalar each (ke, kd, max strain, thickness, stretch stiffness), the chunk
// schedule.
double model_hand_count(const GridCounts& g, double chunk_entries) {
  return 8 * g.particles + 16 * g.springs + 12 * g.triangles + 4 * (g.particles + 1) + 12 * g.triangles +
         16 * g.particles + 5 * 8 + 4 * chunk_entries;
}

// The blocked schedule of a 16^2 grid (1378 springs, below the smallest chunk size): one chunk in one pass.
constexpr double one_chunk_schedule = 2 + 2 + 1 + 2 * (3 + 2) + 22;

}  // namespace

TEST_CASE("a grid model holds its hand-counted bytes: no spring CSR, no per-spring parameters, no UV indices") {
  const BuiltScene b = test::build(test::grid_scene(16, 16, 1.0, Integrator::symplectic));
  const Model& m = b.model;
  const GridCounts g = grid_counts(16);
  REQUIRE(m.spring_count == Index(g.springs));
  REQUIRE(m.tri_count == Index(g.triangles));
  REQUIRE(m.spring_layout == SpringLayout::blocked);
  CHECK(m.particle_spring_offset.empty());
  CHECK(m.spring_ke.uniform());
  CHECK(m.cloths[0].uv_per_vertex);
  CHECK(m.cloths[0].tri_uv.capacity() == 0);
  // one_chunk_schedule: chunk offsets {0, S}, pass offsets
  // {0, 1}, one pass entry; the chunk opens and closes every particle: open and close offsets {0, 1, 1} (the
  // chunk, then the slot of particles in no chunk) and one [begin, end) range each; and one closing count per
  // block of 64 springs, ceil(1378 / 64) = 22.
  REQUIRE(m.spring_chunk_offset.size() == 2);
  CHECK(model_bytes(m) == std::size_t(model_hand_count(g, one_chunk_schedule)));
  CHECK(state_bytes(b.state) == std::size_t(48 * g.particles));
  CHECK(workspace_bytes(make_workspace(m, b.options)) == std::size_t(48 * g.particles));  // f and normals
}

TEST_CASE("a parameter varying by spring kind costs a palette and a byte a spring, kernels that read the CSR get it") {
  SceneDesc s = test::grid_scene(16, 16, 1.0, Integrator::implicit);
  s.cloths[0].bend_scale = 0.5;  // flex springs differ from the others: two stiffness values
  const BuiltScene b = test::build(s);
  const GridCounts g = grid_counts(16);
  CHECK(b.model.spring_ke.paletted());
  CHECK(b.model.spring_ke.size() == 2);
  CHECK(b.model.particle_spring_offset.size() == std::size_t(g.particles + 1));  // implicit reads it
  // ke: two palette entries (16 bytes, against the hand count's one scalar) and one code byte per spring.
  CHECK(model_bytes(b.model) == std::size_t(model_hand_count(g, one_chunk_schedule) + 16 - 8 + g.springs +
                                            4 * (g.particles + 1) + 8 * g.springs));
}

TEST_CASE("the 1024^2 sheet's run holds under 400 bytes a particle by the same count") {
  // What `clothsim run` keeps (tools/cmd_run.cpp): the model, the state, a scratch state, the start positions
  // for the divergence guard, and the workspace. The formula is the one checked against the built model above;
  // the rest of the 400 bytes (about 40 MB) is the program, its libraries and the output buffer.
  const GridCounts g = grid_counts(1024);
  // 6.3 M springs: the automatic chunk size is the largest (springs / 64 > spring_chunk_max). Per chunk: its
  // offset, its pass entry and open/close offsets, and at most a few [begin, end) runs each (a grid chunk's span
  // is one run; 8 is generous); one closing count per block of 64 springs. push_back may double a capacity.
  const double chunks = std::ceil(g.springs / spring_chunk_max);
  const double schedule = 2 * (4 * chunks + spring_max_passes + 3 + 2 * 2 * 8 * chunks) +
                          std::ceil(g.springs / spring_block_size);
  const double held = model_hand_count(g, schedule) + 48 * g.particles + 48 * g.particles + 24 * g.particles +
                      48 * g.particles;
  CHECK(held / g.particles < 360);
}

TEST_CASE("the multigrid levels of an 8 x 8 grid hold their hand-counted bytes") {
  // Levels of 16 and 4 aggregates (tests/unit/multigrid_levels_test.cpp: 2 x 2 squares, then 4 x 4), 42 and 6 edges;
  // 210 of the 306 springs cross between squares, and 18 of the first level's edges between the second's.
  const BuiltScene b = test::build(test::grid_scene(8, 8, 1.0, Integrator::implicit));
  const Multigrid mg = build_multigrid_levels(b.model, 4);
  REQUIRE(mg.levels.size() == 2);
  // One level of n nodes and e edges over nf finer nodes (all with a parent) and `sources` finer edges: parent,
  // members and their offsets, rows (two entries an edge, its neighbour and the edge) and their offsets, sources
  // and their offsets (4 bytes each), the first level's ground offsets; D, D^-1 (48 bytes each), the edge blocks
  // (24 bytes each, float), and three 3-vectors per node. No edge ends and no G: the rows hold the ends, D holds G while it is built.
  auto level = [](double nf, double n, double e, double sources, bool first) {
    return 4 * (nf + (n + 1) + nf + (n + 1) + 4 * e + (e + 1) + sources + (first ? n + 1 : 0)) + 2 * 48 * n +
           24 * e + 3 * 24 * n;
  };
  const double dense = 8 * (2 * 12 * 12 + 12);  // the coarsest level's 3n x 3n matrix, its factor, right-hand side
  CHECK(multigrid_bytes(mg) == std::size_t(level(64, 16, 42, 210, true) + level(16, 4, 6, 18, false) + dense));
  // The workspace adds nothing else for the multigrid: the cycle's output z shares A p's vector (cg_q).
  SceneDesc s = test::grid_scene(8, 8, 1.0, Integrator::implicit);
  s.simulation.preconditioner = Preconditioner::jacobi;
  const BuiltScene plain = test::build(s);
  const Workspace jacobi = make_workspace(plain.model, plain.options);
  s.simulation.preconditioner = Preconditioner::multigrid;
  const BuiltScene with_mg = test::build(s);
  CHECK(workspace_bytes(make_workspace(with_mg.model, with_mg.options)) ==
        workspace_bytes(jacobi) + multigrid_bytes(build_multigrid_levels(with_mg.model)));
}

namespace {

// The implicit workspace of the benchmarks' n^2 sheet (tests/support/sheet_scene.h, two corners pinned), with the
// default multigrid preconditioner and one Newton solve, in bytes a particle, as make_workspace allocates it.
double implicit_sheet_bytes_per_particle(int n) {
  const BuiltScene b = bench::build_sheet(n, Integrator::implicit);
  REQUIRE(b.options.solver.preconditioner == Preconditioner::multigrid);
  REQUIRE(b.options.solver.newton_iterations == 1);
  const Workspace ws = make_workspace(b.model, b.options);
  const double p = b.model.particle_count;
  // Forces and normals, CG's solution, residual, search direction and A p (which also takes the cycle's output),
  // the 3x3 block-Jacobi inverses (48 bytes a particle) and the symmetric spring blocks (24 bytes a spring, float). No
  // velocity change apart from the solution with one Newton solve, no RK4 stages.
  CHECK(workspace_bytes(ws) - multigrid_bytes(ws.multigrid) ==
        std::size_t(6 * 24 * p + 48 * p + 24 * double(b.model.spring_count)));
  // The levels' share by kind of array (docs/performance.md, "Implicit integration", lists them).
  auto bytes = [](const auto&... v) { return double(((v.capacity() * sizeof(v[0])) + ...)); };
  double edge_blocks = 0, diagonals = 0, sources = 0, rows = 0, vectors = 0, members = 0;
  for (const MultigridLevel& l : ws.multigrid.levels) {
    edge_blocks += bytes(l.edge_block);
    diagonals += bytes(l.diag, l.diag_inv);
    sources += bytes(l.source_offset, l.source_index, l.ground_offset, l.ground_index);
    rows += bytes(l.row_offset, l.row_col, l.row_edge);
    vectors += bytes(l.b, l.x, l.t);
    members += bytes(l.parent, l.member_offset, l.member_index);
  }
  const double dense =
      double(multigrid_bytes(ws.multigrid)) - edge_blocks - diagonals - sources - rows - vectors - members;
  MESSAGE(n << "^2 sheet, implicit with the multigrid: " << double(workspace_bytes(ws)) / p
            << " B a particle: spring blocks " << 24.0 * b.model.spring_count / p << ", block-Jacobi inverses 48, "
            << "CG vectors 96, forces and normals 48, multigrid levels " << double(multigrid_bytes(ws.multigrid)) / p
            << " (edge blocks " << edge_blocks / p << ", D and D^-1 " << diagonals / p << ", sources and ground "
            << sources / p << ", rows " << rows / p << ", cycle vectors " << vectors / p << ", parents and members "
            << members / p << ", coarsest dense " << dense / p << ")");
  return double(workspace_bytes(ws)) / p;
}

}  // namespace

TEST_CASE("the implicit workspace of the 1024^2 sheet with the multigrid holds under 500 bytes a particle" *
          doctest::test_suite("slow")) {
  CHECK(implicit_sheet_bytes_per_particle(1024) < 500);
}

TEST_CASE("the implicit workspace with the multigrid holds its hand-counted scratch and under 500 bytes a particle") {
  // 256^2: 65,536 particles, 484.6 bytes each (the 1024^2 sheet above takes some 8 s to build). The 1024^2 figure,
  // 485.8, is 1.2 bytes higher and no more: only the border's share shrinks, so the springs, the first level's
  // edges and their indices per particle rise (5.96 -> 5.99 springs, +1.8 bytes) while the coarsest level's dense
  // matrices spread over more particles (-0.6).
  CHECK(implicit_sheet_bytes_per_particle(256) < 500);

  // One step allocates nothing: every capacity stays as make_workspace left it.
  const BuiltScene small = bench::build_sheet(32, Integrator::implicit);
  Workspace small_ws = make_workspace(small.model, small.options);
  const std::size_t before = workspace_bytes(small_ws);
  State out = small.state;
  step(small.model, small.options, small.state, out, small_ws, 0.01);
  CHECK(workspace_bytes(small_ws) == before);
}
