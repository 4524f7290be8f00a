#pragma once
// Colliders and cloth-side collision topology into Model::collision; nothing when the scene has neither
// colliders nor a self-colliding cloth (model no more than a scene needs).
#include <optional>
#include <vector>

#include "core/mesh_data.h"
#include "core/model.h"

namespace clothsim {

// One collider's mesh before its transform: the OBJ of <static obj>, the first frame of <static sequence> (its
// triangles; the run streams the frames, sim/collider_track.h), none for analytic shapes.
struct ColliderMeshes {
  std::optional<MeshData> mesh;
  int first_frame = 0;  // sequence: frame number of its first frame
  int frame_count = 0;  // sequence: frames first_frame .. first_frame + frame_count - 1
};

// x: the cloth's initial positions (the BVH is built over them).
void build_collision(const SceneDesc& scene, const std::vector<ColliderMeshes>& meshes,
                     const std::vector<Vec3>& x, Model& model);

// Sizes the collision scratch of a workspace (empty when collisions are off).
void make_collision_workspace(const Model& model, CollisionScratch& scratch);

// The BVH over the broad-phase prims (core/bvh_build.cpp): median split on the longest axis of the centroids.
void build_bvh_topology(const std::vector<Vec3>& centroid, Index first_slot, BvhTree& tree);

}  // namespace clothsim
