#pragma once
// Colliders and cloth-side collision topology into Model::collision; nothing when the scene has neither
// colliders nor a self-colliding cloth (model no more than a scene needs).
#include <vector>

#include "core/mesh_data.h"
#include "core/model.h"

namespace clothsim {

// One collider's meshes before its transform: one for <static obj>, one per frame for <static sequence>
// (frames first_frame, first_frame + 1, ...), none for analytic shapes.
struct ColliderMeshes {
  std::vector<MeshData> frames;
  int first_frame = 0;
};

// x: the cloth's initial positions (the BVH is built over them). Throws Error for a sequence whose frames
// differ in vertex count or triangles.
void build_collision(const SceneDesc& scene, const std::vector<ColliderMeshes>& meshes,
                     const std::vector<Vec3>& x, Model& model);

// Sizes the collision scratch of a workspace (empty when collisions are off).
void make_collision_workspace(const Model& model, CollisionScratch& scratch);

// The BVH over the broad-phase prims (core/bvh_build.cpp): median split on the longest axis of the centroids.
void build_bvh_topology(const std::vector<Vec3>& centroid, CollisionModel& c);

}  // namespace clothsim
