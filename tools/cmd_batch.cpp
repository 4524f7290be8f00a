// clothsim batch LIST: many scenes, N at a time, each in its own child process and output folder; a failing
// scene is reported and skipped; a re-run skips completed scenes and resumes interrupted ones.
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <thread>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/json_writer.h"
#include "tools/batch_list.h"
#include "tools/batch_mpi.h"
#include "tools/cli_args.h"
#include "tools/commands.h"
#include "tools/scene_process.h"

namespace clothsim::cli {
namespace {

const char* batch_help =
    "usage: clothsim batch LIST [--jobs N] [--threads-per-job M] [--out DIR] [--checkpoint-every K] [--quiet]\n"
    "  LIST                  a text file of scene paths (one a line, '#' comments) or a folder of *.xml scenes\n"
    "  --jobs N              scenes run at once (default 1)\n"
    "  --threads-per-job M   threads of each scene (default: all cores / N)\n"
    "  --out DIR             each scene writes into DIR/<scene name>/ (default batch_out); the summary goes to\n"
    "                        DIR/summary.json\n"
    "  --checkpoint-every K  checkpoint interval in frames passed to each run (default 10)\n"
    "  --quiet               no progress on stderr\n"
    "A scene that fails is reported and skipped. Running the same batch again skips completed scenes and resumes\n"
    "interrupted ones from their checkpoints.\n"
    "Under mpirun or srun (when built with MPI), rank 0 hands the scenes out one at a time to the other ranks,\n"
    "each running one scene at a time with M threads (--jobs is ignored); --out must be a shared folder.\n"
    "Exit codes: 0 every scene done, 1 some scene failed, 2 bad list or options.";

constexpr int exit_scene_failed = 1;

// Overall progress: scenes and frames done, ETA from this run's frame rate.
class BatchProgress {
 public:
  BatchProgress(const std::vector<BatchScene>& scenes, bool quiet) : scenes_(scenes), quiet_(quiet), tty_(isatty(2)) {
    for (const BatchScene& s : scenes) total_frames_ += s.total_frames;
  }
  void update(int frames_in_flight) {
    if (quiet_ || !tty_) return;
    const int done = frames_finished_ + frames_in_flight;
    std::fprintf(stderr, "\r[%s] scenes %d/%zu  frames %d/%d  ETA %s ", bar(done).c_str(), scenes_done_,
                 scenes_.size(), done, total_frames_, eta(done).c_str());
    std::fflush(stderr);
  }
  void scene_done(const BatchScene& s, bool ran) {
    ++scenes_done_;
    frames_finished_ += s.frames;
    if (ran) frames_run_ += s.frames;
    if (quiet_) return;
    std::fprintf(stderr, "%s[%d/%zu] %s: %s, %d frames, %.2f s%s%s  ETA %s\n", tty_ ? "\r\033[K" : "",
                 scenes_done_, scenes_.size(), s.scene.c_str(), s.status.c_str(), s.frames, s.wall_seconds,
                 s.message.empty() ? "" : " - ", s.message.c_str(), eta(frames_finished_).c_str());
  }
  void finish() {
    if (!quiet_ && tty_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  std::string bar(int done) const {
    const int width = 30, fill = total_frames_ > 0 ? std::min(width, done * width / total_frames_) : 0;
    return std::string(fill, '#') + std::string(width - fill, '.');
  }
  std::string eta(int done) const {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const int ran = std::max(frames_run_, done - skipped_frames());
    if (ran <= 0 || done >= total_frames_) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f s", elapsed / ran * (total_frames_ - done));
    return buf;
  }
  int skipped_frames() const { return frames_finished_ - frames_run_; }

  const std::vector<BatchScene>& scenes_;
  bool quiet_, tty_;
  int total_frames_ = 0, frames_finished_ = 0, frames_run_ = 0, scenes_done_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

std::string format_summary_json(const std::vector<BatchScene>& scenes, double wall_seconds) {
  io::JsonWriter j;
  int failed = 0;
  j.begin_object().key("scenes").begin_array();
  for (const BatchScene& s : scenes) {
    const bool good = s.status == "ok" || s.status == "complete";
    failed += !good;
    j.begin_object()
        .field("scene", std::string_view(s.scene))
        .field("out", std::string_view(s.out_dir))
        .field("frames", s.frames)
        .field("wall_seconds", s.wall_seconds)
        .field("status", std::string_view(s.status))
        .field("exit_code", s.exit_code)
        .field("message", std::string_view(s.message))
        .end_object();
  }
  j.end_array().field("failed", failed).field("wall_seconds", wall_seconds).end_object();
  return j.str() + "\n";
}

// Runs `queue` (indices into `scenes`) `jobs` at a time on this machine.
void run_local(std::vector<BatchScene>& scenes, std::vector<std::size_t> queue, int jobs, int threads,
               int checkpoint_every, BatchProgress& progress) {
  std::reverse(queue.begin(), queue.end());
  struct Running {
    std::size_t index;
    std::unique_ptr<SceneProcess> process;
  };
  std::vector<Running> running;
  while (!queue.empty() || !running.empty()) {
    while (!queue.empty() && int(running.size()) < jobs) {
      BatchScene& s = scenes[queue.back()];
      try {
        running.push_back({queue.back(), std::make_unique<SceneProcess>(s, threads, checkpoint_every)});
      } catch (const std::exception& e) {  // e.g. an output folder that cannot be made: this scene fails, the rest run
        s.status = "failed";
        s.exit_code = exit_bad_input;
        s.message = e.what();
        progress.scene_done(s, false);
      }
      queue.pop_back();
    }
    std::vector<pollfd> fds;
    for (const Running& r : running) fds.push_back({r.process->fd(), POLLIN, 0});
    if (fds.empty()) continue;
    ::poll(fds.data(), fds.size(), 500);
    int in_flight = 0;
    for (std::size_t k = running.size(); k-- > 0;) {
      Running& r = running[k];
      if ((fds[k].revents & (POLLIN | POLLHUP | POLLERR)) && !r.process->read_some()) {
        r.process->finish(scenes[r.index]);
        progress.scene_done(scenes[r.index], true);
        running.erase(running.begin() + std::ptrdiff_t(k));
        continue;
      }
      in_flight += r.process->frames_done();
    }
    progress.update(in_flight);
  }
}

// MPI_Finalize on every way out of cmd_batch once MPI is initialised.
struct MpiSession {
  bool on = false;
  ~MpiSession() {
    if (on) batch_mpi_finalize();
  }
};

void print_summary(const std::vector<BatchScene>& scenes) {
  std::size_t width = 5;
  for (const BatchScene& s : scenes) width = std::max(width, s.scene.size());
  std::printf("%-*s %7s %9s  %-10s %s\n", int(width), "scene", "frames", "wall s", "status", "message");
  for (const BatchScene& s : scenes)
    std::printf("%-*s %7d %9.2f  %-10s %s\n", int(width), s.scene.c_str(), s.frames, s.wall_seconds,
                s.status.c_str(), s.message.c_str());
}

}  // namespace

int cmd_batch(int argc, char** argv) {
  const auto wall0 = std::chrono::steady_clock::now();
  const Args args =
      parse_args(argc, argv, {"--jobs", "--threads-per-job", "--out", "--checkpoint-every"}, {"--quiet"});
  if (args.help) { std::puts(batch_help); return exit_ok; }
  if (args.positional.size() != 1) throw UsageError("expected one list file or folder of scenes");
  const int jobs = args.has("--jobs") ? parse_int("--jobs", args.get("--jobs"), 1) : 1;
  const int cores = std::max(1, int(std::thread::hardware_concurrency()));
  const int threads = args.has("--threads-per-job") ? parse_int("--threads-per-job", args.get("--threads-per-job"), 1)
                                                    : std::max(1, cores / jobs);
  const int checkpoint_every =
      args.has("--checkpoint-every") ? parse_int("--checkpoint-every", args.get("--checkpoint-every"), 0) : 10;
  const std::string out = args.get("--out", "batch_out");
  MpiSession mpi;
  int rank = 0;
  mpi.on = batch_mpi_start(rank);
  io::ensure_writable_dir(out);

  std::vector<BatchScene> scenes = read_batch_list(args.positional[0], out);
  if (mpi.on && rank != 0) {  // a worker: runs what rank 0 hands it
    batch_mpi_run(scenes, {}, threads, checkpoint_every, {});
    return exit_ok;
  }
  BatchProgress progress(scenes, args.has("--quiet"));

  // Completed scenes (marker left by an earlier batch) are skipped; the rest run `jobs` at a time.
  std::vector<std::size_t> queue;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    if (batch_done(scenes[i])) {
      scenes[i].status = "complete";
      scenes[i].exit_code = 0;
      scenes[i].frames = scenes[i].total_frames;
      scenes[i].message = "done by an earlier batch";
      progress.scene_done(scenes[i], false);
    } else {
      queue.push_back(i);
    }
  }
  if (mpi.on) {
    batch_mpi_run(scenes, queue, threads, checkpoint_every,
                  [&](const BatchScene& s) { progress.scene_done(s, true); });
  } else {
    run_local(scenes, queue, jobs, threads, checkpoint_every, progress);
  }
  progress.finish();

  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  io::write_file_atomic(out + "/summary.json", format_summary_json(scenes, wall));
  print_summary(scenes);
  const bool all_good = std::all_of(scenes.begin(), scenes.end(),
                                    [](const BatchScene& s) { return s.status == "ok" || s.status == "complete"; });
  return all_good ? exit_ok : exit_scene_failed;
}

}  // namespace clothsim::cli
