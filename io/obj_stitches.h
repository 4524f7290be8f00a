#pragma once
// Sewing records in a cloth OBJ, in Codim-IPC's format: `stitch i j k w` (0-based vertex indices: vertex i
// belongs at (1 - w) x_j + w x_k) and `seam N` lines that group them. Other readers skip both keys.
#include <string>

#include "core/mesh_data.h"

namespace clothsim::io {

// Appends the text's stitch records to mesh.stitch_* and counts its seam lines. Throws Error(path, line) for a
// malformed record, an index outside 0..vertex_count-1 or w outside [0, 1]; mesh.positions must be read already.
void read_obj_stitches(const std::string& path, const std::string& text, MeshData& mesh);

}  // namespace clothsim::io
