#include "io/rest_shape.h"

#include <algorithm>

#include "core/error.h"
#include "io/obj_reader.h"

namespace clothsim::io {

std::vector<Vec3> read_rest_shape(const SceneDesc& scene, const ClothDesc& cloth, const MeshData& mesh) {
  if (cloth.rest.empty()) return {};
  MeshData rest = read_obj(cloth.rest);
  const std::string own = mesh.source.empty() ? "the grid" : "'" + mesh.source + "'";
  const std::string where = "cloth '" + cloth.name + "': rest mesh '" + cloth.rest + "' ";
  if (rest.vertex_count() != mesh.vertex_count() || rest.triangle_count() != mesh.triangle_count())
    throw Error(scene.path, cloth.line,
                where + "has " + std::to_string(rest.vertex_count()) + " vertices and " +
                    std::to_string(rest.triangle_count()) + " triangles; expected the " +
                    std::to_string(mesh.vertex_count()) + " vertices and " + std::to_string(mesh.triangle_count()) +
                    " triangles of " + own);
  const auto diff = std::mismatch(rest.tri_index.begin(), rest.tri_index.end(), mesh.tri_index.begin());
  if (diff.first != rest.tri_index.end()) {
    const std::size_t t = std::size_t(diff.first - rest.tri_index.begin()) / 3;
    auto corners = [&](const std::vector<Index>& tri) {
      return std::to_string(tri[3 * t]) + " " + std::to_string(tri[3 * t + 1]) + " " + std::to_string(tri[3 * t + 2]);
    };
    throw Error(scene.path, cloth.line,
                where + "differs in triangle " + std::to_string(t) + " (vertices " + corners(rest.tri_index) +
                    ", counted from 0); expected the triangles of " + own + " in the same order (" +
                    corners(mesh.tri_index) + ")");
  }
  return std::move(rest.positions);
}

}  // namespace clothsim::io
