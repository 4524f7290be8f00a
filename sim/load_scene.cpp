#include "sim/load_scene.h"

#include <chrono>

#include "io/checkpoint.h"
#include "io/collider_reader.h"
#include "io/cloth_maps.h"
#include "io/obj_reader.h"
#include "io/rest_shape.h"
#include "io/scene_xml.h"
#include "io/text_file.h"
#include "sim/cpu_clock.h"
#include "systems/auto_step.h"

namespace clothsim::sim {

LoadedScene load_scene(const std::string& path) {
  using clock = std::chrono::steady_clock;
  LoadedScene s;
  const double c0 = process_cpu_seconds();
  const auto t0 = clock::now();
  const std::string text = io::read_text_file(path, "a scene XML file");  // read once: it may be a pipe
  s.desc = io::parse_scene(path, text);
  std::vector<MeshData> meshes;
  for (const ClothDesc& c : s.desc.cloths) meshes.push_back(c.obj.empty() ? make_cloth_grid(c) : io::read_obj(c.obj));
  for (std::size_t c = 0; c < meshes.size(); ++c) meshes[c].params = io::sample_cloth_maps(s.desc, s.desc.cloths[c], meshes[c]);
  for (std::size_t c = 0; c < meshes.size(); ++c) meshes[c].rest_positions = io::read_rest_shape(s.desc, s.desc.cloths[c], meshes[c]);
  // Every collider frame is read here once, checked and fingerprinted, but only the first is kept: the run
  // streams the frames (sim/collider_track.h).
  std::uint64_t fingerprint = io::inputs_fingerprint(text, meshes);
  const std::vector<ColliderMeshes> colliders =
      io::read_colliders(s.desc, [&](const MeshData& m) { fingerprint = io::fingerprint_mesh(m, fingerprint); });
  s.inputs_fingerprint = fingerprint;
  const auto t1 = clock::now();
  const double c1 = process_cpu_seconds();
  s.built = build_model(s.desc, std::move(meshes));  // consumed: a large mesh is not held twice
  build_collision(s.desc, colliders, s.built.state.x, s.built.model);
  if (s.built.options.auto_step) choose_auto_step(s.built.model, s.built.options, s.built.state.x, path);
  s.load_seconds = std::chrono::duration<double>(t1 - t0).count();
  s.topology_seconds = std::chrono::duration<double>(clock::now() - t1).count();
  s.load_cpu_seconds = c1 - c0;
  s.topology_cpu_seconds = process_cpu_seconds() - c1;
  return s;
}

}  // namespace clothsim::sim
