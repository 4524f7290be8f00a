#pragma once
// Reads the meshes of a scene's colliders: one OBJ for <static obj>, the frames start..end of a
// <static sequence> (the run of '#' in its name is the zero-padded frame number).
#include <functional>
#include <string>
#include <vector>

#include "core/build_collision.h"
#include "core/scene_desc.h"

namespace clothsim::io {

// One entry per scene.colliders: the mesh of <static obj>, the first frame of a sequence (with its frame range),
// nothing for spheres and planes. Every frame of a sequence is read once and checked to have the first frame's
// triangles, then dropped: memory holds one frame however long the sequence. each_mesh, when given, sees every
// mesh read, in scene order and frame order (the run's input fingerprint). Throws Error naming the file of a
// missing frame or one whose vertices or triangles differ.
std::vector<ColliderMeshes> read_colliders(const SceneDesc& scene,
                                           const std::function<void(const MeshData&)>& each_mesh = {});

// Frame `frame` (a frame number, as in the file name) of sequence collider `collider` of the scene, untransformed.
MeshData read_collider_frame(const SceneDesc& scene, std::size_t collider, int frame);

// The path of one frame of a sequence pattern: the last run of '#' in the file name becomes the frame number,
// zero-padded to the run's length ("body.####.obj", 7 -> "body.0007.obj").
std::string sequence_frame_path(const std::string& pattern, int frame);

}  // namespace clothsim::io
