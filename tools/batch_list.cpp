#include "tools/batch_list.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include "core/error.h"
#include "io/scene_xml.h"
#include "io/text_file.h"

namespace clothsim::cli {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  return b == std::string::npos ? "" : s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> scene_paths(const std::string& list) {
  namespace fs = std::filesystem;
  std::vector<std::string> paths;
  std::error_code ec;
  if (fs::is_directory(list, ec)) {
    for (const auto& e : fs::directory_iterator(list))
      if (e.is_regular_file() && e.path().extension() == ".xml") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
    if (paths.empty()) throw Error(list, "folder holds no .xml scene; expected scene files or a list file");
    return paths;
  }
  const std::string text = io::read_text_file(list, "a list of scene files, one a line");
  const fs::path base = fs::path(list).parent_path();
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string line = trim(text.substr(pos, std::min(end, text.find('#', pos)) - pos));
    pos = end + 1;
    if (line.empty()) continue;
    const fs::path p(line);
    paths.push_back(p.is_absolute() ? line : (base / p).lexically_normal().string());
  }
  if (paths.empty()) throw Error(list, "no scene listed; expected one scene path a line ('#' starts a comment)");
  return paths;
}

}  // namespace

std::vector<BatchScene> read_batch_list(const std::string& list, const std::string& out_dir) {
  std::vector<BatchScene> scenes;
  std::set<std::string> names;
  for (const std::string& path : scene_paths(list)) {
    BatchScene s;
    s.scene = path;
    const std::string stem = std::filesystem::path(path).stem().string();
    std::string name = stem;
    for (int k = 2; !names.insert(name).second; ++k) name = stem + "-" + std::to_string(k);
    s.out_dir = (std::filesystem::path(out_dir) / name).string();
    try {  // for the progress bar only; the scene's own run reports a bad file
      const SceneDesc d = io::read_scene(path);
      s.total_frames = d.simulation.end_frame - d.simulation.start_frame + 1;
    } catch (const Error&) {
    }
    scenes.push_back(std::move(s));
  }
  return scenes;
}

}  // namespace clothsim::cli
