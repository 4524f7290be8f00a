#include "tools/scene_loader.h"

#include <chrono>

#include "io/collider_reader.h"
#include "io/cloth_maps.h"
#include "io/obj_reader.h"
#include "io/scene_xml.h"

namespace clothsim::cli {

LoadedScene load_scene(const std::string& path) {
  using clock = std::chrono::steady_clock;
  LoadedScene s;
  const auto t0 = clock::now();
  s.desc = io::read_scene(path);
  std::vector<MeshData> meshes;
  for (const ClothDesc& c : s.desc.cloths) meshes.push_back(c.obj.empty() ? make_cloth_grid(c) : io::read_obj(c.obj));
  const std::vector<ColliderMeshes> colliders = io::read_colliders(s.desc);
  for (std::size_t c = 0; c < meshes.size(); ++c) meshes[c].params = io::sample_cloth_maps(s.desc, s.desc.cloths[c], meshes[c]);
  const auto t1 = clock::now();
  s.built = build_model(s.desc, meshes);
  build_collision(s.desc, colliders, s.built.state.x, s.built.model);
  s.load_seconds = std::chrono::duration<double>(t1 - t0).count();
  s.topology_seconds = std::chrono::duration<double>(clock::now() - t1).count();
  return s;
}

}  // namespace clothsim::cli
