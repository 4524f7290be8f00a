#include "core/attachments.h"

#include <limits>

#include "core/error.h"
#include "core/triangle_distance.h"

namespace clothsim {

void mark_attachments(const SceneDesc& scene, const ClothDesc& cloth, const MeshData& mesh, Index base,
                      std::vector<char>& pinned_flag, Model& m) {
  if (cloth.attach.empty()) return;
  const Index n = mesh.vertex_count();
  std::vector<Index> collider_of(n, -1);  // the first <attach> that lists each vertex
  for (std::size_t k = 0; k < cloth.attach.size(); ++k) {
    const AttachDesc& a = cloth.attach[k];
    const std::string where = "cloth '" + cloth.name + "' <attach collider=\"" + a.collider + "\">: ";
    Index collider = -1;
    for (std::size_t c = 0; c < scene.colliders.size(); ++c)
      if (collider < 0 && scene.colliders[c].name == a.collider) collider = Index(c);
    if (collider < 0) {
      std::string names;
      for (const ColliderDesc& c : scene.colliders) names += (names.empty() ? "'" : ", '") + c.name + "'";
      throw Error(scene.path, a.line, where + "no collider has that name; expected one of: " +
                                          (names.empty() ? std::string("(the scene has no collider)") : names));
    }
    const ColliderShape shape = scene.colliders[collider].shape;
    if (shape == ColliderShape::sphere || shape == ColliderShape::plane)
      throw Error(scene.path, a.line,
                  where + "the collider is a " + (shape == ColliderShape::sphere ? "sphere" : "plane") +
                      "; expected a mesh collider (<static obj> or <static sequence>). An analytic collider does not "
                      "move: hold the vertices with <pins> instead");
    auto attach = [&](Index v) {
      if (collider_of[v] < 0) collider_of[v] = collider;
    };
    for (Index v : a.vertices) {
      if (v < 0 || v >= n)
        throw Error(scene.path, a.line,
                    where + "vertex " + std::to_string(v) + " is out of range (the mesh has " + std::to_string(n) +
                        " vertices, numbered from 0)");
      attach(v);
    }
    const std::vector<char>& map = k < mesh.params.attached.size() ? mesh.params.attached[k] : std::vector<char>{};
    if (!map.empty() && Index(map.size()) != n)
      throw Error(scene.path, a.line, where + "the map has the wrong size; expected one value per vertex");
    for (Index v = 0; v < Index(map.size()); ++v)
      if (map[v]) attach(v);
  }
  for (Index v = 0; v < n; ++v) {
    if (collider_of[v] < 0) continue;
    pinned_flag[base + v] = 1;
    m.attach_particle.push_back(base + v);
    m.attach_collider.push_back(collider_of[v]);
  }
}

void bind_attachments(const SceneDesc& scene, const std::vector<Vec3>& x, Model& m) {
  const CollisionModel& c = m.collision;
  const std::size_t n = m.attach_particle.size();
  m.attach_tri.assign(n, -1);
  m.attach_weight.assign(n, Vec3::Zero());
  m.attach_offset.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& p = x[m.attach_particle[k]];
    const ColliderInfo& ci = c.colliders[m.attach_collider[k]];
    Real best = std::numeric_limits<Real>::infinity();
    for (Index t = ci.tri_begin; t < ci.tri_end; ++t) {
      const Index* v = &c.mesh_tri_index[3 * t];
      const Vec3 &a = c.mesh_x[v[0]], &b = c.mesh_x[v[1]], &cc = c.mesh_x[v[2]];
      if (!((b - a).cross(cc - a).squaredNorm() > 0)) continue;  // no normal to offset along
      const Real d = point_triangle_distance(p, a, b, cc);
      if (d < best) {
        best = d;
        m.attach_tri[k] = t;
      }
    }
    if (m.attach_tri[k] < 0)
      throw Error(scene.path, scene.colliders[m.attach_collider[k]].line,
                  "collider '" + ci.name + "' has no triangle of non-zero area; expected one to attach cloth to");
    // Weights of the projection on the plane (unclamped, so the bound point is the vertex itself even where the
    // nearest point is on an edge) from the 2x2 normal equations, and the height over the plane.
    const Index* v = &c.mesh_tri_index[3 * m.attach_tri[k]];
    const Vec3 &a = c.mesh_x[v[0]], e1 = c.mesh_x[v[1]] - a, e2 = c.mesh_x[v[2]] - a, r = p - a;
    const Real a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2), b1 = e1.dot(r), b2 = e2.dot(r);
    const Real det = a11 * a22 - a12 * a12;
    const Real u = (b1 * a22 - a12 * b2) / det, w = (a11 * b2 - a12 * b1) / det;
    m.attach_weight[k] = Vec3(1 - u - w, u, w);
    m.attach_offset[k] = e1.cross(e2).normalized().dot(r);
  }
}

}  // namespace clothsim
