#pragma once
// SceneDesc + one MeshData per cloth -> the immutable Model, the run's SimOptions and the initial State.
#include <vector>

#include "core/mesh_data.h"
#include "core/model.h"

namespace clothsim {

struct BuiltScene {
  Model model;
  SimOptions options;
  State state;
};

// meshes[i] is cloth i's mesh before its transform (a generated grid for grid cloths).
// Throws Error naming the scene file and the cloth's line for settings the mesh cannot honour.
BuiltScene build_model(const SceneDesc& scene, const std::vector<MeshData>& meshes);
// The same, consuming the meshes: their UVs move into the model and each mesh is freed once its cloth is built,
// so a large mesh is not held twice (docs/performance.md, "Memory and loading").
BuiltScene build_model(const SceneDesc& scene, std::vector<MeshData>&& meshes);

// The mesh for a grid cloth (empty MeshData for OBJ cloths, which io reads).
MeshData make_cloth_grid(const ClothDesc& cloth);

}  // namespace clothsim
