#pragma once
// The scenes of a batch: from a list file (one path a line, '#' starts a comment, relative paths are relative
// to the list's folder) or from a folder (its *.xml files, sorted), each given its own output folder.
#include <string>
#include <vector>

namespace clothsim::cli {

struct BatchScene {
  std::string scene;     // path of the scene file
  std::string out_dir;   // <out>/<scene stem>, with -2, -3... when stems repeat
  int total_frames = 0;  // endFrame - startFrame + 1 when the scene reads, else 0 (the run reports why)
  // filled in by the batch
  std::string status = "pending";  // ok, complete (done by an earlier batch), bad input, diverged, crashed
  int exit_code = -1;
  int frames = 0;                  // frames on disk at the end
  double wall_seconds = 0;
  std::string message;             // the error line of a failed scene
};

// Throws Error(list, line, ...) for an unreadable list or an empty one.
std::vector<BatchScene> read_batch_list(const std::string& list, const std::string& out_dir);

}  // namespace clothsim::cli
