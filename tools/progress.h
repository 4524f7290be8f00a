#pragma once
#include <chrono>

namespace clothsim::cli {

// Progress on stderr: a live bar (frames, frames/s, ETA) on a terminal, one line per frame otherwise,
// nothing when quiet.
class Progress {
 public:
  Progress(int total_frames, bool quiet);
  void frame_done(int done, int frame_number);
  void finish();

 private:
  int total_;
  bool quiet_, tty_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace clothsim::cli
