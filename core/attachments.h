#pragma once
// Attachments: cloth vertices bound to a mesh collider (a waistband to a body, a collar to a shoulder). At the
// first frame each attached vertex is bound to the nearest triangle of its collider by the barycentric weights of
// its projection on the triangle's plane and its signed distance along the unit normal; every step it is placed
// at that point of the moving triangle (systems/attachments.h). An attached vertex is a pin (infinite mass) for
// every stage; only its position is prescribed (docs/garments.md, Attachments).
#include <vector>

#include "core/mesh_data.h"
#include "core/model.h"

namespace clothsim {

// Marks the vertices of cloth c's <attach> elements as pinned (pinned_flag, indexed from `base`) and lists them in
// model.attach_particle / attach_collider in vertex order; a vertex that several <attach> list goes to the first.
// Throws Error (scene file, the element's line) for an unknown collider, an analytic one (sphere or plane), an
// index out of range or a map of the wrong size.
void mark_attachments(const SceneDesc& scene, const ClothDesc& cloth, const MeshData& mesh, Index base,
                      std::vector<char>& pinned_flag, Model& model);

// Binds every listed particle to the nearest non-degenerate triangle of its collider at the first frame
// (collision.mesh_x), lowest triangle on ties. x: the particles' initial positions. Needs the collision tables.
// Throws Error (scene file, the collider's line) for a collider without a triangle of non-zero area.
void bind_attachments(const SceneDesc& scene, const std::vector<Vec3>& x, Model& model);

// The point a binding follows on triangle (a, b, c): w0 a + w1 b + w2 c + offset n, n the unit normal.
inline Vec3 attachment_point(const Vec3& w, Real offset, const Vec3& a, const Vec3& b, const Vec3& c) {
  return w[0] * a + w[1] * b + w[2] * c + offset * (b - a).cross(c - a).normalized();
}

}  // namespace clothsim
