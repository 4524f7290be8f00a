#pragma once
// <cloth rest="pattern.obj">: the rest shape of a cloth from another mesh with the same vertices and triangles
// (a garment draped on a body keeps its flat pattern's rest lengths; docs/garments.md, Rest shape).
#include <vector>

#include "core/mesh_data.h"
#include "core/scene_desc.h"

namespace clothsim::io {

// The rest mesh's positions (cloth.rest; empty when the cloth has none). Throws Error naming the scene file, the
// cloth's line and both meshes when the vertex count or the triangle list (the same corners, in the same order)
// differs from the cloth mesh's, and the reader's errors for the rest mesh itself.
std::vector<Vec3> read_rest_shape(const SceneDesc& scene, const ClothDesc& cloth, const MeshData& mesh);

}  // namespace clothsim::io
