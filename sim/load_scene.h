#pragma once
// Scene file -> meshes -> Model, timed by phase: what `run`, `validate`, the studies and the tests load.
#include <cstdint>
#include <string>

#include "core/build_model.h"
#include "core/scene_desc.h"

namespace clothsim::sim {

struct LoadedScene {
  SceneDesc desc;
  BuiltScene built;
  std::uint64_t inputs_fingerprint = 0;  // of every input file's content (io::inputs_fingerprint)
  double load_seconds = 0;      // reading the scene and the meshes
  double topology_seconds = 0;  // edges, bend springs, CSR, masses
  // The same phases in CPU time of the whole process (all threads): what a loaded machine cannot inflate.
  double load_cpu_seconds = 0, topology_cpu_seconds = 0;
};

LoadedScene load_scene(const std::string& path);

}  // namespace clothsim::sim
