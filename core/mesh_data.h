#pragma once
// A triangle mesh as read from disk or generated: plain data, before it becomes cloth.
#include <string>
#include <vector>

#include "core/math.h"
#include "core/vertex_params.h"

namespace clothsim {

struct MeshData {
  std::string source;            // file it came from ("" for a generated mesh), for error messages
  std::vector<Vec3> positions;   // m (vertex_count)
  std::vector<Vec2> uvs;         // texture coordinates (uv_count); may be empty
  std::vector<Index> tri_index;  // vertex indices, counter-clockwise (3 * triangle_count)
  std::vector<Index> tri_uv;     // uv indices per corner (3 * triangle_count), or empty without UVs
  int polygons_triangulated = 0; // faces with more than 3 corners that were split into a fan
  VertexParams params;           // sampled from the cloth's maps; empty arrays for uniform values
  // sewing (Codim-IPC's `stitch i j k w`, 0-based): vertex stitch_a belongs at (1 - w) x_b + w x_c (stitch count)
  std::vector<Index> stitch_a, stitch_b, stitch_c;
  std::vector<Real> stitch_w;
  Index seam_count = 0;          // `seam N` group lines read (they only group stitches)
  std::vector<Vec3> rest_positions;  // <cloth rest>: the rest mesh's positions, m (vertex_count), or empty

  Index vertex_count() const { return static_cast<Index>(positions.size()); }
  Index stitch_count() const { return static_cast<Index>(stitch_a.size()); }
  Index triangle_count() const { return static_cast<Index>(tri_index.size() / 3); }
};

}  // namespace clothsim
