#include <doctest/doctest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "core/multigrid_levels.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;

TEST_CASE("an 8 x 8 grid aggregates into 2 x 2 squares, then 4 x 4, with the hand-counted coarse edges") {
  // Provot's springs: pairing the structural neighbour of lowest index first gives horizontal pairs; two pairs
  // one above the other share two structural and two shear springs (4 k), side by side one structural and two
  // flex springs (3 k), so the second round stacks them: 2 x 2 squares of particles.
  SceneDesc scene = test::grid_scene(8, 8, 1.0, Integrator::implicit);
  const BuiltScene b = test::build(scene);
  const Multigrid mg = build_multigrid_levels(b.model, 4);
  REQUIRE(mg.levels.size() == 2);
  const MultigridLevel& first = mg.levels[0];
  CHECK(first.node_count == 16);
  for (Index j = 0; j < 8; ++j)
    for (Index i = 0; i < 8; ++i) CHECK(first.parent[8 * j + i] == 4 * (j / 2) + i / 2);
  // A 4 x 4 grid of aggregates joined to its 8 neighbours: 12 horizontal, 12 vertical and 2 x 9 diagonal edges.
  CHECK(first.edge_count == 42);
  // Every spring is inside one square (left out) or summed into exactly one coarse edge.
  Index inside = 0;
  for (Index s = 0; s < b.model.spring_count; ++s) inside += first.parent[b.model.spring_a[s]] == first.parent[b.model.spring_b[s]];
  CHECK(inside == 16 * 6);  // a square holds 4 structural and 2 shear springs
  CHECK(Index(first.source_index.size()) == b.model.spring_count - inside);
  CHECK(first.ground_index.empty());
  CHECK(mg.levels[1].node_count == 4);
  CHECK(mg.levels[1].edge_count == 6);  // 2 x 2 aggregates, all joined to each other
  CHECK(mg.dense_coarsest);
  CHECK(mg.dense.rows() == 12);
}

TEST_CASE("pinned particles belong to no aggregate, their springs ground the aggregates they reach") {
  SceneDesc scene = test::grid_scene(11, 9, 1.0, Integrator::implicit);
  scene.cloths[0].pins = {0, 10, 50};
  const BuiltScene b = test::build(scene);
  const Model& m = b.model;
  const Multigrid mg = build_multigrid_levels(m, 3);
  REQUIRE(mg.levels.size() >= 2);
  Index finer = m.particle_count;
  for (std::size_t l = 0; l < mg.levels.size(); ++l) {
    const MultigridLevel& L = mg.levels[l];
    REQUIRE(Index(L.parent.size()) == finer);
    // Each aggregate has one to four members, and the members list is the parent map inverted.
    for (Index n = 0; n < L.node_count; ++n) {
      const Index size = L.member_offset[n + 1] - L.member_offset[n];
      CHECK(size >= 1);
      CHECK(size <= 4);
      for (Index k = L.member_offset[n]; k < L.member_offset[n + 1]; ++k) CHECK(L.parent[L.member_index[k]] == n);
    }
    // Edges join distinct aggregates, once per pair, and each is in the rows of both its ends.
    std::set<std::pair<Index, Index>> pairs;
    std::vector<int> rows_of(std::size_t(L.edge_count), 0);
    for (Index n = 0; n < L.node_count; ++n)
      for (Index k = L.row_offset[n]; k < L.row_offset[n + 1]; ++k) {
        CHECK(L.row_col[k] != n);
        ++rows_of[L.row_edge[k]];
        if (n < L.row_col[k]) pairs.insert({n, L.row_col[k]});
      }
    CHECK(Index(pairs.size()) == L.edge_count);
    CHECK(std::count(rows_of.begin(), rows_of.end(), 2) == L.edge_count);
    finer = L.node_count;
  }
  const MultigridLevel& first = mg.levels[0];
  for (Index p : {0, 10, 50}) CHECK(first.parent[p] == -1);
  CHECK(first.member_offset.back() == m.particle_count - 3);
  // Ground springs: exactly those with one pinned end.
  Index to_pins = 0;
  for (Index s = 0; s < m.spring_count; ++s)
    to_pins += (m.particle_inv_mass[m.spring_a[s]] > 0) != (m.particle_inv_mass[m.spring_b[s]] > 0);
  CHECK(Index(first.ground_index.size()) == to_pins);
  CHECK(to_pins > 0);
  CHECK(mg.levels.back().node_count <= 3);
}

TEST_CASE("disconnected pieces stop the coarsening where each piece is one node") {
  // Two 2 x 2 sheets side by side: each becomes one aggregate and no spring joins them.
  SceneDesc scene = test::grid_scene(2, 2, 1.0, Integrator::implicit);
  scene.cloths.push_back(scene.cloths[0]);
  scene.cloths[1].name = "other";
  scene.cloths[1].transform.translate = Vec3(3, 0, 0);
  const BuiltScene b = test::build(scene);
  const Multigrid mg = build_multigrid_levels(b.model, 1);
  REQUIRE(mg.levels.size() == 1);
  CHECK(mg.levels[0].node_count == 2);
  CHECK(mg.levels[0].edge_count == 0);
}
