#pragma once
// One scene of a batch, run as a child process of this same binary (`clothsim run ... --resume`): a crash,
// an abort or an out-of-memory kill in one scene cannot take the batch down, each child gets its own TBB
// thread limit (tbb::global_control is process-wide), and its memory returns to the system when it ends.
// Its stdout and stderr come back through a pipe: progress lines are parsed, everything goes to run.log.
#include <sys/types.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "tools/batch_list.h"

namespace clothsim::cli {

class SceneProcess {
 public:
  // Creates s.out_dir and starts the child. Throws Error when the folder or the process cannot be made.
  SceneProcess(const BatchScene& s, int threads, int checkpoint_every);
  ~SceneProcess();
  SceneProcess(const SceneProcess&) = delete;
  SceneProcess& operator=(const SceneProcess&) = delete;

  int fd() const { return fd_; }
  // Reads what the child wrote; false once it closed its output (then call finish).
  bool read_some();
  int frames_done() const { return frames_done_; }
  // Waits for the child and fills status, exit_code, frames, wall_seconds and message of `s`.
  void finish(BatchScene& s);

 private:
  void take_line(const std::string& line);

  pid_t pid_ = -1;
  int fd_ = -1;
  std::FILE* log_ = nullptr;
  std::string pending_, error_;
  int frames_done_ = 0;
  std::chrono::steady_clock::time_point start_;
};

// Path of the marker a completed scene leaves in its output folder, so a re-run batch skips it.
std::string batch_done_marker(const BatchScene& s);
// Whether that marker is there and names this scene (a marker of another scene of the same stem does not count).
bool batch_done(const BatchScene& s);

}  // namespace clothsim::cli
