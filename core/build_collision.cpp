#include "core/build_collision.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

#include "core/attachments.h"
#include "core/seams.h"
#include "core/topology.h"
#include "core/transform.h"

namespace clothsim {
namespace {

// Plane normals transform by the inverse transpose (R S^-1 n); radii scale by the largest scale factor.
void place_analytic(const ColliderDesc& d, ColliderInfo& c) {
  const Mat3 r = rotation_xyz_degrees(d.transform.rotate);
  c.center = apply_transform(d.transform, d.center);
  c.radius = d.radius * d.transform.scale.cwiseAbs().maxCoeff();
  c.point = apply_transform(d.transform, d.point);
  c.normal = (r * d.normal.cwiseQuotient(d.transform.scale)).normalized();
}

// Unique edges of the triangles t < tri_count with keep(t); each edge remembers its lowest triangle, which alone
// reports it to the edge-edge tests, so an edge found through both its triangles is tested once.
template <class Keep>
void build_edges(const std::vector<Index>& tri_index, Index tri_count, Keep&& keep, std::vector<Index>& edge_a,
                 std::vector<Index>& edge_b, std::vector<Index>& first_tri, std::vector<Index>& tri_edge) {
  std::vector<std::array<Index, 3>> e;  // (a, b, tri), a < b
  for (Index t = 0; t < tri_count; ++t) {
    if (!keep(t)) continue;
    for (int k = 0; k < 3; ++k) {
      const Index a = tri_index[3 * t + k], b = tri_index[3 * t + (k + 1) % 3];
      e.push_back({std::min(a, b), std::max(a, b), t});
    }
  }
  std::sort(e.begin(), e.end());
  tri_edge.assign(3 * std::size_t(tri_count), -1);
  for (std::size_t k = 0; k < e.size(); ++k) {
    if (k == 0 || e[k][0] != e[k - 1][0] || e[k][1] != e[k - 1][1]) {
      edge_a.push_back(e[k][0]);
      edge_b.push_back(e[k][1]);
      first_tri.push_back(e[k][2]);
    }
    const Index edge = Index(edge_a.size()) - 1, t = e[k][2];
    for (int j = 0; j < 3; ++j)
      if (tri_edge[3 * t + j] < 0) { tri_edge[3 * t + j] = edge; break; }
  }
}

// Which cloths meet which: a cloth itself when it self-collides (expensive: off by default), two different
// cloths when both take part in cloth-cloth collision (on by default).
void build_cloth_pairs(const Model& m, CollisionModel& c) {
  const Index n = Index(m.cloths.size());
  c.cloth_count = n;
  c.cloth_pair.assign(std::size_t(n) * n, 0);
  for (Index a = 0; a < n; ++a)
    for (Index b = 0; b < n; ++b) {
      const bool meet = a == b ? m.cloths[a].self_collision : m.cloths[a].cloth_collision && m.cloths[b].cloth_collision;
      c.cloth_pair[std::size_t(a) * n + b] = meet;
      c.cloth_contact = c.cloth_contact || meet;
    }
}

// Each collider mesh vertex's triangles as a CSR (a counting sort, triangles ascending), and the lowest of them,
// which alone reports the vertex to the cloth triangles its box meets.
void build_vertex_tris(CollisionModel& c) {
  const Index nv = c.mesh_vertex_count, nt = Index(c.mesh_tri_collider.size());
  c.mesh_vertex_tri_offset.assign(std::size_t(nv) + 1, 0);
  for (Index v : c.mesh_tri_index) ++c.mesh_vertex_tri_offset[v + 1];
  for (Index v = 0; v < nv; ++v) c.mesh_vertex_tri_offset[v + 1] += c.mesh_vertex_tri_offset[v];
  std::vector<Index> fill(c.mesh_vertex_tri_offset.begin(), c.mesh_vertex_tri_offset.end() - 1);
  c.mesh_vertex_tri.resize(c.mesh_tri_index.size());
  for (Index t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) c.mesh_vertex_tri[fill[c.mesh_tri_index[3 * t + k]]++] = t;
  c.mesh_vertex_first_tri.assign(nv, -1);
  for (Index v = 0; v < nv; ++v)
    if (c.mesh_vertex_tri_offset[v] < c.mesh_vertex_tri_offset[v + 1])
      c.mesh_vertex_first_tri[v] = c.mesh_vertex_tri[c.mesh_vertex_tri_offset[v]];
}

}  // namespace

void build_collision(const SceneDesc& scene, const std::vector<ColliderMeshes>& meshes, const std::vector<Vec3>& x,
                     Model& m) {
  CollisionModel& c = m.collision;
  build_cloth_pairs(m, c);
  c.enabled = c.cloth_contact || !scene.colliders.empty();
  if (!c.enabled) {
    c = CollisionModel();  // model no more than the scene needs
    return;
  }
  c.iterations = scene.simulation.collision_iterations;
  c.zone_iterations = scene.simulation.impact_zone_iterations;
  c.broad_phase = scene.simulation.broad_phase;

  if (m.stitch_count > 0) build_seams(m, c);
  c.particle_cloth.resize(m.particle_count);
  c.tri_contact.assign(m.tri_count, 0);
  for (std::size_t k = 0; k < m.cloths.size(); ++k) {
    const ClothInfo& ci = m.cloths[k];
    const std::uint8_t meets_some = std::any_of(c.cloth_pair.begin() + k * c.cloth_count,
                                                c.cloth_pair.begin() + (k + 1) * c.cloth_count,
                                                [](std::uint8_t p) { return p != 0; });
    for (Index i = ci.particle_begin; i < ci.particle_end; ++i) c.particle_cloth[i] = Index(k);
    for (Index t = ci.tri_begin; t < ci.tri_end; ++t) c.tri_contact[t] = meets_some;
    c.max_thickness = std::max(c.max_thickness, ci.thickness);
  }
  for (Index i = 0; i < m.particle_count; ++i) c.max_thickness = std::max(c.max_thickness, m.particle_thickness[i]);

  for (std::size_t k = 0; k < scene.colliders.size(); ++k) {
    const ColliderDesc& d = scene.colliders[k];
    ColliderInfo ci;
    ci.name = d.name;
    ci.start_frame = scene.simulation.start_frame;
    ci.fps = scene.simulation.fps;
    ci.shape = d.shape;
    ci.friction = d.friction;
    place_analytic(d, ci);
    if (d.shape == ColliderShape::mesh || d.shape == ColliderShape::sequence) {
      const MeshData& first = *meshes[k].mesh;
      ci.vertex_begin = c.mesh_vertex_count;
      ci.vertex_end = ci.vertex_begin + first.vertex_count();
      ci.tri_begin = Index(c.mesh_tri_collider.size());
      ci.tri_end = ci.tri_begin + first.triangle_count();
      const Topology topo = build_topology(first);
      ci.closed = topo.boundary_edges == 0 && topo.nonmanifold_edges == 0;
      for (const Vec3& p : first.positions) c.mesh_x.push_back(apply_transform(d.transform, p));
      for (Index t : first.tri_index) c.mesh_tri_index.push_back(ci.vertex_begin + t);
      c.mesh_tri_collider.insert(c.mesh_tri_collider.end(), first.triangle_count(), Index(k));
      c.mesh_vertex_count = ci.vertex_end;
      if (d.shape == ColliderShape::sequence) {
        ci.first_frame = meshes[k].first_frame;
        ci.frame_count = meshes[k].frame_count;
        c.animated = true;
      }
    }
    c.colliders.push_back(std::move(ci));
  }

  // Edges for the edge-edge tests: those of cloths that meet some cloth among themselves, every cloth's against
  // collider meshes.
  const bool meshes_present = !c.mesh_tri_collider.empty();
  if (c.cloth_contact || meshes_present) {
    build_edges(m.tri_index, m.tri_count, [&](Index t) { return meshes_present || c.tri_contact[t]; }, c.edge_a,
                c.edge_b, c.edge_first_tri, c.tri_edge);
    for (Index t : c.edge_first_tri) c.edge_contact.push_back(c.tri_contact[t]);
  }
  if (meshes_present) {
    build_edges(c.mesh_tri_index, Index(c.mesh_tri_collider.size()), [](Index) { return true; }, c.mesh_edge_a,
                c.mesh_edge_b, c.mesh_edge_first_tri, c.mesh_tri_edge);
    build_vertex_tris(c);
  }

  // Teschner et al. 2003 §4: a cell near the size of a hashed box. A triangle's box is about an edge long
  // plus the thickness on each side, so the cell is mean edge + 2h (measured by bench/collision_bench.cpp:
  // docs/performance.md, "Spatial hash against BVH").
  Real edge_sum = 0;
  for (Index t = 0; t < m.tri_count; ++t)
    for (int k = 0; k < 3; ++k)
      edge_sum += (x[m.tri_index[3 * t + k]] - x[m.tri_index[3 * t + (k + 1) % 3]]).norm();
  const Real mean_edge = m.tri_count > 0 ? edge_sum / (3.0 * m.tri_count) : 1.0;
  c.cell_size = mean_edge + 2 * c.max_thickness;

  std::vector<Vec3> centroid;
  for (Index t = 0; t < m.tri_count; ++t)
    if (c.tri_contact[t]) {
      c.prim.push_back(t);
      centroid.push_back((x[m.tri_index[3 * t]] + x[m.tri_index[3 * t + 1]] + x[m.tri_index[3 * t + 2]]) / 3);
    }
  c.cloth_prim_count = Index(c.prim.size());
  if (c.broad_phase == BroadPhase::bvh) build_bvh_topology(centroid, 0, c.cloth_tree);
  centroid.clear();
  for (Index t = 0; t < Index(c.mesh_tri_collider.size()); ++t) {
    c.prim.push_back(m.tri_count + t);
    const Index* v = &c.mesh_tri_index[3 * t];
    centroid.push_back((c.mesh_x[v[0]] + c.mesh_x[v[1]] + c.mesh_x[v[2]]) / 3);
  }
  build_bvh_topology(centroid, c.cloth_prim_count, c.collider_tree);
  bind_attachments(scene, x, m);
}

void make_collision_workspace(const Model& m, CollisionScratch& s) {
  const CollisionModel& c = m.collision;
  if (!c.enabled) return;
  s.collider_x0.assign(c.mesh_vertex_count, Vec3::Zero());
  s.collider_x1 = c.mesh_x;
  s.collider_x0 = c.mesh_x;
  s.prim_box.resize(c.prim.size());
  s.cloth_node_box.resize(std::size_t(c.cloth_tree.node_count()));
  s.collider_node_box.resize(std::size_t(c.collider_tree.node_count()));
  s.hash.prim_cells.assign(c.prim.size() + 1, 0);
  s.acc_dv.assign(3 * std::size_t(m.particle_count), 0);
  s.acc_dx.assign(3 * std::size_t(m.particle_count), 0);
  s.acc_count.assign(m.particle_count, 0);
  s.crossed.assign(m.particle_count, 0);
  s.deep_collider.assign(m.particle_count, -1);
  // A first capacity for the contact buffer; a pass that finds more grows it (systems/collision/contacts.h).
  s.contacts.resize(std::min<std::size_t>(std::size_t(m.particle_count), 4096));
  s.collider_frames.assign(c.colliders.size(), {});
  for (std::size_t k = 0; k < c.colliders.size(); ++k) {
    const ColliderInfo& ci = c.colliders[k];
    if (ci.shape == ColliderShape::sequence)
      s.collider_frames[k].x.resize(std::size_t(collider_window_frames) * (ci.vertex_end - ci.vertex_begin));
  }
  if (c.impact_zones()) {
    const std::size_t nodes = std::size_t(m.particle_count) + c.mesh_vertex_count;
    s.zones.parent.resize(nodes);
    s.zones.flag.assign(nodes, 0);
    s.zones.slot.assign(nodes, -1);
    s.zones.offset.assign(nodes + 1, 0);
    s.zones.member.resize(nodes);
    s.zones.reach.reserve(std::size_t(m.particle_count));
    s.zones.reach_box.reserve(std::size_t(m.particle_count));
  }
}

}  // namespace clothsim
