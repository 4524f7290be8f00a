#include "io/collider_reader.h"

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

std::vector<ColliderMeshes> read_colliders(const SceneDesc& scene) {
  std::vector<ColliderMeshes> out(scene.colliders.size());
  for (std::size_t k = 0; k < scene.colliders.size(); ++k) {
    const ColliderDesc& d = scene.colliders[k];
    // Collider meshes are read leniently: a body may carry a sliver triangle that a cloth may not.
    if (d.shape == ColliderShape::mesh) {
      out[k].frames.push_back(read_obj(d.obj, MeshCheck::lenient));
    } else if (d.shape == ColliderShape::sequence) {
      out[k].first_frame = scene.simulation.start_frame;
      for (int f = scene.simulation.start_frame; f <= scene.simulation.end_frame; ++f) {
        const std::string path = sequence_frame_path(d.sequence, f);
        if (!std::filesystem::is_regular_file(path))
          throw Error(path, "frame " + std::to_string(f) + " of collider '" + d.name +
                                "' is missing; expected one OBJ per frame " +
                                std::to_string(scene.simulation.start_frame) + ".." +
                                std::to_string(scene.simulation.end_frame) + " (scene " + scene.path + ")");
        out[k].frames.push_back(read_obj(path, MeshCheck::lenient));
      }
    }
  }
  return out;
}

}  // namespace clothsim::io
