#include "io/collider_reader.h"

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "io/obj_reader.h"

namespace clothsim::io {

std::string sequence_frame_path(const std::string& pattern, int frame) {
  const std::size_t name_start = pattern.find_last_of('/') + 1;  // npos + 1 == 0
  const std::size_t last = pattern.find_last_of('#');
  if (last == std::string::npos || last < name_start) return pattern;
  std::size_t first = last;
  while (first > name_start && pattern[first - 1] == '#') --first;
  std::string number = std::to_string(frame);
  const std::size_t width = last - first + 1;
  if (number.size() < width) number.insert(0, width - number.size(), '0');
  return pattern.substr(0, first) + number + pattern.substr(last + 1);
}

MeshData read_collider_frame(const SceneDesc& scene, std::size_t collider, int frame) {
  const ColliderDesc& d = scene.colliders[collider];
  const std::string path = sequence_frame_path(d.sequence, frame);
  if (!std::filesystem::is_regular_file(path))
    throw Error(path, "frame " + std::to_string(frame) + " of collider '" + d.name +
                          "' is missing; expected one OBJ per frame " + std::to_string(scene.simulation.start_frame) +
                          ".." + std::to_string(scene.simulation.end_frame) + " (scene " + scene.path + ")");
  // Collider meshes are read leniently: a body may carry a sliver triangle that a cloth may not.
  return read_obj(path, MeshCheck::lenient);
}

namespace {

// A sequence's frames move the first frame's vertices: the same count and the same triangles.
void check_same_triangles(const ColliderDesc& d, const MeshData& first, const MeshData& f) {
  if (f.vertex_count() == first.vertex_count() && f.triangle_count() == first.triangle_count() &&
      f.tri_index != first.tri_index) {
    const auto t = (std::mismatch(f.tri_index.begin(), f.tri_index.end(), first.tri_index.begin()).first -
                    f.tri_index.begin()) / 3;
    throw Error(f.source, "collider '" + d.name + "': triangle " + std::to_string(t + 1) +
                              " has other corners (or another winding) than in " + first.source +
                              "; expected every frame to have the same triangles, only moved vertices");
  }
  if (f.vertex_count() != first.vertex_count() || f.tri_index != first.tri_index)
    throw Error(f.source, "collider '" + d.name + "': frame has " + std::to_string(f.vertex_count()) +
                              " vertices and " + std::to_string(f.triangle_count()) + " triangles; expected " +
                              std::to_string(first.vertex_count()) + " and " + std::to_string(first.triangle_count()) +
                              " like " + first.source);
}

}  // namespace

std::vector<ColliderMeshes> read_colliders(const SceneDesc& scene,
                                           const std::function<void(const MeshData&)>& each_mesh) {
  std::vector<ColliderMeshes> out(scene.colliders.size());
  for (std::size_t k = 0; k < scene.colliders.size(); ++k) {
    const ColliderDesc& d = scene.colliders[k];
    if (d.shape == ColliderShape::mesh) {
      out[k].mesh = read_obj(d.obj, MeshCheck::lenient);
      if (each_mesh) each_mesh(*out[k].mesh);
    } else if (d.shape == ColliderShape::sequence) {
      out[k].first_frame = scene.simulation.start_frame;
      out[k].frame_count = scene.simulation.end_frame - scene.simulation.start_frame + 1;
      for (int f = scene.simulation.start_frame; f <= scene.simulation.end_frame; ++f) {
        MeshData frame = read_collider_frame(scene, k, f);
        if (out[k].mesh) check_same_triangles(d, *out[k].mesh, frame);
        if (each_mesh) each_mesh(frame);
        if (!out[k].mesh) out[k].mesh = std::move(frame);
      }
    }
  }
  return out;
}

}  // namespace clothsim::io
