#include "tools/run_outputs.h"

#include <filesystem>
#include <set>

#include "core/error.h"
#include "io/atomic_file.h"
#include "tools/cli_args.h"

namespace clothsim::cli {

std::vector<std::string> prepare_run_outputs(const SceneDesc& scene, const std::string* out,
                                             const std::string* stats) {
  const std::string& scene_path = scene.path;
  if (out && out->empty()) throw UsageError("--out expects a folder, got an empty name");
  if (stats && stats->empty()) throw UsageError("--stats expects a file name, got an empty name");
  std::vector<std::string> dirs;
  std::set<std::string> names;
  for (const ClothDesc& c : scene.cloths) {
    dirs.push_back(out ? *out : c.save_dir);
    if (!names.insert(io::normalised_path(dirs.back() + "/" + c.save_name)).second)
      throw Error(scene_path, "two cloths write '" + c.save_name + "' into " + dirs.back() +
                                  "; expected distinct saveName values");
  }
  for (const std::string& d : std::set<std::string>(dirs.begin(), dirs.end())) io::ensure_writable_dir(d);
  if (stats) io::check_output_file(*stats);
  // Temporaries are named <final name>.tmp<pid> (io/atomic_file.h): frames and materials start with
  // "<saveName>.", checkpoints with "<scene stem>." in the first folder.
  for (std::size_t c = 0; c < dirs.size(); ++c) io::remove_stale_temporaries(dirs[c], scene.cloths[c].save_name + ".");
  if (!dirs.empty()) io::remove_stale_temporaries(dirs.front(), std::filesystem::path(scene_path).stem().string() + ".");
  if (stats) {
    const std::filesystem::path p(*stats);
    io::remove_stale_temporaries(p.parent_path().string(), p.filename().string() + ".");
  }
  return dirs;
}

}  // namespace clothsim::cli
