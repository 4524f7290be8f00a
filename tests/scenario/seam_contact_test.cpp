// Seam-aware contact: vertices joined by a stitch are neighbours, like the two ends of a mesh edge, so the
// triangles and edges that touch at a seam are neither contact pairs nor counted intersections.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <vector>

#include "core/build_collision.h"
#include "core/build_model.h"
#include "core/grid.h"
#include "io/obj_reader.h"
#include "systems/collision/collide.h"
#include "systems/collision/collision_check.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;

namespace {

// Panel A, the 3 x 3 grid g, and panel B, g's vertices placed by place(x); with `sew`, B's first column
// (9, 12, 15) stitched to A's last (2, 5, 8), vertex to vertex. Built with the collision model of `s`.
template <class Place>
BuiltScene two_panels(const SceneDesc& s, const MeshData& g, Place&& place, bool sew) {
  MeshData mesh = g;
  const Index n = g.vertex_count();
  for (const Vec3& x : g.positions) mesh.positions.push_back(place(x));
  for (Index t : g.tri_index) mesh.tri_index.push_back(n + t);
  mesh.uvs.clear();
  mesh.tri_uv.clear();
  if (sew)
    for (int j = 0; j < 3; ++j) {
      mesh.stitch_a.push_back(n + 3 * j);
      mesh.stitch_b.push_back(3 * j + 2);
      mesh.stitch_c.push_back(3 * j + 2);
      mesh.stitch_w.push_back(0);
    }
  BuiltScene b = build_model(s, std::vector<MeshData>{mesh});
  build_collision(s, {}, b.state.x, b.model);
  return b;
}

// Panel A: 3 x 3 vertices, 0.2 m square in the plane y = 0 (x, z in [-0.1, 0.1]). Panel B: the same grid tilted
// down by atan(0.12) about the z axis, its first column at x = 0.08, y = +2 mm, so B's first strip of triangles
// passes through A's last strip (x in [0, 0.1]) at x = 0.0967. With `sew`, B's first column is stitched to A's
// last column (vertex to vertex).
BuiltScene lapped_panels(bool sew) {
  const auto place = [](const Vec3& x) {
    const Real u = x.x() + 0.1;  // 0, 0.1, 0.2 along the panel
    return Vec3(0.08 + u, 0.002 - 0.12 * u, x.z());
  };
  return two_panels(test::self_colliding_scene(0.001), make_grid_mesh(3, 3, 0.2, 0.2), place, sew);
}

// Particle i's row of the seam table.
std::vector<Index> seam_row(const CollisionModel& c, Index i) {
  return {c.seam_index.begin() + c.seam_offset[i], c.seam_index.begin() + c.seam_offset[i + 1]};
}

}  // namespace

TEST_CASE("seam adjacency: a sewn vertex is a neighbour of the vertices it is sewn to, not of theirs") {
  const BuiltScene b = lapped_panels(true);
  const CollisionModel& c = b.model.collision;
  CHECK(c.joined(9, 2));  // B's first vertex and A's vertex (2, 0)
  CHECK(c.joined(2, 9));
  CHECK(c.joined(4, 4));
  CHECK_FALSE(c.joined(9, 1));
  CHECK_FALSE(c.joined(9, 5));
  const Index tri_a[3] = {1, 4, 2}, tri_far[3] = {0, 3, 1};
  CHECK_FALSE(c.vertex_meets_cloth_triangle(9, tri_a));  // corner 2 is sewn to 9
  CHECK(c.vertex_meets_cloth_triangle(9, tri_far));
  CHECK(c.edges_adjacent(9, 10, 1, 2));
  CHECK_FALSE(c.edges_adjacent(10, 11, 1, 2));
}

// Three 3 x 3 panels side by side (A: vertices 0-8, B: 9-17, C: 18-26), apart in x so that nothing touches;
// the stitches only make the seam graph.
BuiltScene three_panels(const std::vector<std::array<Real, 4>>& stitches) {
  const SceneDesc s = test::self_colliding_scene(0.001);
  const MeshData g = make_grid_mesh(3, 3, 0.2, 0.2);
  MeshData mesh;
  for (int p = 0; p < 3; ++p) {
    const Index n = Index(mesh.positions.size());
    for (const Vec3& x : g.positions) mesh.positions.push_back(x + Vec3(0.5 * p, 0, 0));
    for (Index t : g.tri_index) mesh.tri_index.push_back(n + t);
  }
  for (const auto& st : stitches) {
    mesh.stitch_a.push_back(Index(st[0]));
    mesh.stitch_b.push_back(Index(st[1]));
    mesh.stitch_c.push_back(Index(st[2]));
    mesh.stitch_w.push_back(st[3]);
  }
  BuiltScene b = build_model(s, std::vector<MeshData>{mesh});
  build_collision(s, {}, b.state.x, b.model);
  return b;
}

TEST_CASE("seam adjacency: vertices sewn to coincide through a chain are one point, a stitch inside an edge is not") {
  // C's 18 on B's 9 (w = 0), B's 9 on A's 2 (w = 1 on the edge 1-2): 2, 9 and 18 are one point of the garment.
  // C's 20 sewn half way along B's edge 11-14 joins 11 and 14 only. A's 6 on B's 15 (w = 0) is a pair apart.
  const BuiltScene b = three_panels({{18, 9, 9, 0}, {9, 1, 2, 1}, {20, 11, 14, 0.5}, {6, 15, 15, 0}});
  const CollisionModel& c = b.model.collision;
  // Hand count of each row: the group, and the groups of the partners of its members.
  CHECK(c.joined(18, 2));  // through 9: not a stitch of its own
  CHECK(c.joined(2, 18));
  CHECK(c.joined(18, 9));
  CHECK(c.joined(18, 1));  // 9 is stitched to the edge 1-2, and 18 is 9
  CHECK(c.joined(9, 1));
  CHECK(c.joined(20, 11));
  CHECK(c.joined(20, 14));
  CHECK(c.joined(6, 15));
  CHECK_FALSE(c.joined(20, 9));  // 20 lies inside 11-14: no chain through it
  CHECK_FALSE(c.joined(11, 14));  // both sewn to 20, not to each other
  CHECK_FALSE(c.joined(6, 2));
  CHECK_FALSE(c.joined(18, 15));
  CHECK(c.joined(1, 18));  // 1 is stitched to 9, so to all of its point
  CHECK(seam_row(c, 18) == std::vector<Index>{1, 2, 9});
  CHECK(seam_row(c, 20) == std::vector<Index>{11, 14});
  const Index tri_a[3] = {1, 4, 2};
  CHECK_FALSE(c.vertex_meets_cloth_triangle(18, tri_a));  // a corner is 18's own point
}

// Two 3 x 3 panels 4 mm apart vertex to vertex (a 8 mm square each), B's first column (9, 12, 15) sewn to A's
// last (2, 5, 8), far apart in space: only the seam graph matters. The grid's triangles cut each square along
// (i + 1, j)-(i, j + 1), so 2-4, 5-7, 10-12 and 13-15 are 5.66 mm diagonals.
BuiltScene fine_seam(Real thickness) {
  return two_panels(test::self_colliding_scene(thickness), make_grid_mesh(3, 3, 0.008, 0.008),
                    [](const Vec3& x) { return Vec3(x + Vec3(0.5, 0, 0)); }, true);
}

TEST_CASE("seam reach: particles within two thicknesses of each other at rest through a seam are neighbours") {
  // 3 mm thick: a reach of 6 mm. By hand, pair (2, 9): 2's ball is {2: 0, 1: 4, 5: 4, 4: 5.66 mm}, 9's
  // {9: 0, 10: 4, 12: 4}; pair (5, 12): 5's {5: 0, 2, 4, 8: 4, 7: 5.66}, 12's {12: 0, 9, 13, 15: 4, 10: 5.66};
  // a pair joins u and v when their two distances sum to 6 mm or less.
  const BuiltScene b = fine_seam(0.003);
  const CollisionModel& c = b.model.collision;
  CHECK(seam_row(c, 9) == std::vector<Index>{1, 2, 4, 5});
  CHECK(seam_row(c, 12) == std::vector<Index>{2, 4, 5, 7, 8});
  CHECK(seam_row(c, 2) == std::vector<Index>{9, 10, 12});
  CHECK(seam_row(c, 10) == std::vector<Index>{2, 5});
  CHECK_FALSE(c.joined(0, 4));  // 5.66 mm apart on one panel: the mesh alone joins nothing
  CHECK_FALSE(c.joined(1, 10));  // 4 + 4 mm
  const Index next_ring[3] = {4, 5, 7};
  CHECK_FALSE(c.vertex_meets_cloth_triangle(9, next_ring));
  // 1 mm thick (a 2 mm reach): the sewn rows alone.
  const BuiltScene thin = fine_seam(0.001);
  CHECK(seam_row(thin.model.collision, 9) == std::vector<Index>{2});
  CHECK(seam_row(thin.model.collision, 2) == std::vector<Index>{9});
  CHECK(seam_row(thin.model.collision, 12) == std::vector<Index>{5});
}

TEST_CASE("panels lapped at a seam: intersections and contact pairs without the stitches, none with them") {
  for (bool sew : {false, true}) {
    CAPTURE(sew);
    BuiltScene b = lapped_panels(sew);
    const Index crossing = count_intersecting_triangles(b.model, b.state.x);
    if (!sew) CHECK(crossing > 0);
    else CHECK(crossing == 0);
    // One collision stage on the resting panels: contacts only where nothing is sewn.
    Workspace ws = make_workspace(b.model, b.options);
    State out = b.state;
    const std::int64_t contacts = collide(b.model, b.state, out, ws, b.options.dt).contacts;
    if (!sew) CHECK(contacts > 0);
    else CHECK(contacts == 0);
  }
}

TEST_CASE("the draped Codim-IPC dress: its intersecting triangle pairs are seams (skips without ../shared/data)") {
  const std::filesystem::path data = test::shared_data();
  const std::filesystem::path cipc = data / "garments" / "cipc";
  if (data.empty() || !std::filesystem::exists(cipc / "dress_knife_stage.obj")) return;
  // The drape's first 15,656 vertices and 29,456 triangles are the dress, numbered as the stage, whose stitch
  // records sew it.
  const MeshData stage = io::read_obj((cipc / "dress_knife_stage.obj").string());
  MeshData drape = io::read_obj((cipc / "dress_knife_drape_with_body.obj").string(), io::MeshCheck::lenient);
  REQUIRE(stage.stitch_count() == 851);
  drape.positions.resize(stage.positions.size());
  drape.tri_index.resize(stage.tri_index.size());
  REQUIRE(drape.tri_index == stage.tri_index);
  drape.uvs.clear();
  drape.tri_uv.clear();
  const SceneDesc s = test::self_colliding_scene(0.003);
  // Without the stitches clothsim's count and an independent check agree on 427 pairs, all within 6 mm of a
  // stitched vertex; with the seams as neighbours none is left.
  MeshData mesh = drape;
  mesh.stitch_a = stage.stitch_a;
  mesh.stitch_b = stage.stitch_b;
  mesh.stitch_c = stage.stitch_c;
  mesh.stitch_w = stage.stitch_w;
  BuiltScene b = build_model(s, std::vector<MeshData>{mesh});
  build_collision(s, {}, b.state.x, b.model);
  CHECK(count_intersecting_triangles(b.model, b.state.x) == 0);
  // The seam rows, counted by an independent script (a union-find over the 545 stitches with w = 0 or 1, then
  // each stitched vertex's group and its partners' groups): 6,832 sewn entries, where the direct links alone
  // give 3,340. The 395 groups have 2 (331), 3 (30) or 4 (34) vertices: junctions of up to four panels. The
  // seam reach (6 mm at 3 mm thick: a Dijkstra over the triangle edges from both ends of every sewn pair, in
  // the same script) brings the table to 13,276.
  CHECK(b.model.collision.seam_index.size() == 13276);
}
