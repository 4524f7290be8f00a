#pragma once
// The material file that lets an output sequence open textured: one <saveName>.mtl per cloth with a colour
// texture, beside its frames, which reference it with mtllib/usemtl (io/obj_writer).
#include <string>

#include "core/model.h"

namespace clothsim::io {

// Path of a cloth's material file: <dir>/<saveName>.mtl
std::string material_path(const std::string& dir, const std::string& save_name);

// The .mtl text: one material named after saveName whose map_Kd is the texture's path relative to `dir`
// (absolute when no relative path exists), so the folder can move together with the texture's folder.
std::string format_material(const std::string& dir, const ClothInfo& cloth, const std::string& save_name);

// Writes format_material atomically; nothing for a cloth without a texture.
void write_material(const std::string& dir, const ClothInfo& cloth, const std::string& save_name);

}  // namespace clothsim::io
