// Spring and edge counts checked by hand.
#include <doctest/doctest.h>

#include "core/grid.h"
#include "core/topology.h"
#include "tests/support/scene_fixtures.h"

using namespace clothsim;

namespace {

MeshData mesh_of(std::vector<Vec3> p, std::vector<Index> tris) {
  MeshData m;
  m.positions = std::move(p);
  m.tri_index = std::move(tris);
  return m;
}

}  // namespace

TEST_CASE("a quad of two triangles has 5 edge springs and 1 bend spring") {
  const Topology t = build_topology(mesh_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {0, 1, 2, 0, 2, 3}));
  CHECK(t.edge_count() == 5);
  CHECK(t.bend_count() == 1);
  CHECK(t.bend_a[0] == 1);  // the two vertices opposite the diagonal 0-2
  CHECK(t.bend_b[0] == 3);
  CHECK(t.boundary_edges == 4);
  CHECK(t.pieces == 1);
}

TEST_CASE("closed meshes have E = 3F/2 edges and one bend spring per edge") {
  // Octahedron: 6 vertices, 8 faces, 12 edges.
  const std::vector<Vec3> p{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const std::vector<Index> f{0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  const Topology t = build_topology(mesh_of(p, f));
  CHECK(t.edge_count() == 3 * 8 / 2);
  CHECK(t.bend_count() == 12);
  CHECK(t.boundary_edges == 0);
  CHECK(t.nonmanifold_edges == 0);
}

TEST_CASE("a non-manifold edge is counted and gets no bend spring, pieces and degenerate triangles are counted") {
  // Three triangles on the edge 0-1, a separate triangle, and one with a repeated corner.
  const std::vector<Vec3> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1},
                            {5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
  const Topology t = build_topology(mesh_of(p, {0, 1, 2, 1, 0, 3, 0, 1, 4, 5, 6, 7, 5, 5, 6}));
  CHECK(t.nonmanifold_edges == 1);
  CHECK(t.bend_count() == 0);
  CHECK(t.pieces == 2);
  CHECK(t.degenerate_triangles == 1);
  CHECK(t.edge_count() == 7 + 3);
}

TEST_CASE("an NX x NY grid has the known structural, shear and flex spring counts") {
  for (auto [nx, ny] : {std::pair{2, 2}, std::pair{5, 3}, std::pair{32, 20}}) {
    const SpringList s = make_grid_springs(nx, ny);
    int count[spring_kind_count] = {};
    for (SpringKind k : s.kind) ++count[int(k)];
    CAPTURE(nx);
    CAPTURE(ny);
    CHECK(count[int(SpringKind::structural)] == (nx - 1) * ny + nx * (ny - 1));
    CHECK(count[int(SpringKind::shear)] == 2 * (nx - 1) * (ny - 1));
    CHECK(count[int(SpringKind::flex)] == (nx - 2) * ny + nx * (ny - 2));
  }
}

TEST_CASE("grid layout: XZ plane centred at the origin, vertex (i, j) at j*NX + i, UVs over 0..1") {
  const MeshData m = make_grid_mesh(4, 3, 2.0, 1.0);
  CHECK(m.vertex_count() == 12);
  CHECK(m.triangle_count() == 2 * 3 * 2);
  CHECK(m.positions[0] == Vec3(-1, 0, -0.5));
  CHECK(m.positions[2 * 4 + 3] == Vec3(1, 0, 0.5));
  CHECK(m.uvs[1 * 4 + 2].isApprox(Vec2(2.0 / 3, 0.5)));
  // Every triangle faces +Y.
  for (Index t = 0; t < m.triangle_count(); ++t) {
    const Vec3 &a = m.positions[m.tri_index[3 * t]], &b = m.positions[m.tri_index[3 * t + 1]],
               &c = m.positions[m.tri_index[3 * t + 2]];
    CHECK((b - a).cross(c - a).y() > 0);
  }
}

TEST_CASE("mass from areal density: a grid's total mass is density x area at any resolution") {
  for (int n : {4, 17, 40}) {
    SceneDesc s = test::grid_scene(n, n, 1.5, Integrator::symplectic);
    s.cloths[0].density = 0.3;
    const BuiltScene b = test::build(s);
    Real mass = 0;
    for (Real im : b.model.particle_inv_mass) mass += 1 / im;
    CHECK(mass == doctest::Approx(0.3 * 1.5 * 1.5).epsilon(1e-12));
  }
}
