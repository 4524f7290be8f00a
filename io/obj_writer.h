#pragma once
#include <span>
#include <string>

#include "core/model.h"

namespace clothsim::io {

// Path of a cloth's frame: <dir>/<saveName>.<frame, 4 digits>.obj
std::string frame_path(const std::string& dir, const std::string& save_name, int frame);

// One cloth's frame as OBJ text: v (9 significant digits), vt (the input UVs), vn (the given unit normals),
// and f v/vt/vn (or v//vn without UVs), 1-based, local to the cloth; with a texture, mtllib <saveName>.mtl
// and usemtl <saveName> (see io/mtl_writer.h). save_name: the cloth's saveName (an output name: the scene's, not
// the Model's).
std::string format_frame(const Model& model, const ClothInfo& cloth, const std::string& save_name,
                         std::span<const Vec3> x, std::span<const Vec3> normal, int frame);

// Writes format_frame atomically (temporary name, then rename).
void write_frame(const std::string& path, const Model& model, const ClothInfo& cloth, const std::string& save_name,
                 std::span<const Vec3> x, std::span<const Vec3> normal, int frame);

}  // namespace clothsim::io
