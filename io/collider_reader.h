#pragma once
// Reads the meshes of a scene's colliders: one OBJ for <static obj>, every frame start..end of a
// <static sequence> (the run of '#' in its name is the zero-padded frame number).
#include <string>
#include <vector>

#include "core/build_collision.h"
#include "core/scene_desc.h"

namespace clothsim::io {

// One entry per scene.colliders (empty frames for spheres and planes). Throws Error naming the file of a
// missing frame.
std::vector<ColliderMeshes> read_colliders(const SceneDesc& scene);

// The path of one frame of a sequence pattern: the last run of '#' in the file name becomes the frame number,
// zero-padded to the run's length ("body.####.obj", 7 -> "body.0007.obj").
std::string sequence_frame_path(const std::string& pattern, int frame);

}  // namespace clothsim::io
