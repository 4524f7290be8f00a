#pragma once
// Samples a cloth's parameter maps at its vertices (docs/maps.md), giving the plain per-vertex arrays that
// core's build_model takes. A vertex referenced with several UVs (a seam) takes the mean of its samples.
#include "core/mesh_data.h"
#include "core/scene_desc.h"
#include "io/texture_map.h"

namespace clothsim::io {

// Throws Error naming the scene file, the element's line and the attribute for a map on a mesh without UVs
// and for an unreadable, empty or truncated image.
VertexParams sample_cloth_maps(const SceneDesc& scene, const ClothDesc& cloth, const MeshData& mesh);

// Grey level in [0, 1] of each vertex (vertex_count): the mean over the distinct UVs its corners use; 0 for
// a vertex no triangle references.
std::vector<Real> vertex_grey(const GreyImage& image, const MeshData& mesh);

}  // namespace clothsim::io
