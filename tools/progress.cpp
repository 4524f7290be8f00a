#include "tools/progress.h"

#include <unistd.h>

#include <cstdio>
#include <string>

namespace clothsim::cli {

Progress::Progress(int total_frames, bool quiet)
    : total_(total_frames), quiet_(quiet), tty_(::isatty(2) != 0), start_(std::chrono::steady_clock::now()) {}

void Progress::frame_done(int done, int frame_number) {
  if (quiet_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? done / elapsed : 0;
  const double eta = rate > 0 ? (total_ - done) / rate : 0;
  if (tty_) {
    const int width = 30, fill = total_ > 0 ? done * width / total_ : width;
    std::fprintf(stderr, "\r[%s%s] %d/%d frames  %.1f frames/s  ETA %.1f s ", std::string(fill, '#').c_str(),
                 std::string(width - fill, '.').c_str(), done, total_, rate, eta);
  } else {
    std::fprintf(stderr, "frame %04d  %d/%d  %.2f frames/s  ETA %.1f s\n", frame_number, done, total_, rate, eta);
  }
  std::fflush(stderr);
}

void Progress::finish() {
  if (!quiet_ && tty_) std::fprintf(stderr, "\n");
}

}  // namespace clothsim::cli
