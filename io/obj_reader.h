#pragma once
#include <string>
#include <vector>

#include "core/mesh_data.h"

namespace clothsim::io {

enum class MeshCheck {
  strict,   // reject zero-length edges and zero-area triangles (a cloth must have none)
  lenient,  // accept them, for `clothsim info`, which counts them
};

// Reads an OBJ (tinyobjloader) into a MeshData: polygons split into fans (counted in polygons_triangulated),
// UVs kept when every corner has one. Throws Error with the file, the line where known and what was expected
// for a missing file, a malformed number, a NaN or infinite coordinate, an index out of range, no faces, and
// (strict) a zero-length edge or zero-area triangle.
MeshData read_obj(const std::string& path, MeshCheck check = MeshCheck::strict);

}  // namespace clothsim::io
