#include "tools/scene_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "core/error.h"
#include "io/atomic_file.h"

extern char** environ;

namespace clothsim::cli {
namespace {

std::string self_exe() {
  char buf[4096];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) throw Error("/proc/self/exe", "cannot find the clothsim binary to run scenes with");
  return std::string(buf, std::size_t(n));
}

}  // namespace

std::string batch_done_marker(const BatchScene& s) { return s.out_dir + "/batch.done"; }

namespace {
// The marker names the scene it completed: output folders are named by file stem in list order, so after the
// list is reordered a folder may belong to another scene of the same stem.
std::string marker_text(const BatchScene& s) { return "scene " + io::normalised_path(s.scene) + "\n"; }
}  // namespace

bool batch_done(const BatchScene& s) {
  std::ifstream in(batch_done_marker(s), std::ios::binary);
  std::string line;
  return in && std::getline(in, line) && line + "\n" == marker_text(s);
}

SceneProcess::SceneProcess(const BatchScene& s, int threads, int checkpoint_every)
    : start_(std::chrono::steady_clock::now()) {
  io::ensure_writable_dir(s.out_dir);
  const std::string log_path = s.out_dir + "/run.log";
  log_ = std::fopen(log_path.c_str(), "a");
  if (!log_) throw Error(log_path, std::string("cannot open log (") + std::strerror(errno) + ")");
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw Error(s.scene, std::string("cannot create a pipe: ") + std::strerror(errno));
  const std::string exe = self_exe();
  std::vector<std::string> args = {exe, "run", s.scene, "--out", s.out_dir, "--threads", std::to_string(threads),
                                   "--checkpoint-every", std::to_string(checkpoint_every), "--resume",
                                   "--stats", s.out_dir + "/stats.json"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  const int rc = posix_spawn(&pid_, exe.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  fd_ = fds[0];
  if (rc != 0) {
    ::close(fd_);
    fd_ = -1;
    std::fclose(log_);
    log_ = nullptr;
    throw Error(s.scene, std::string("cannot start a clothsim process: ") + std::strerror(rc));
  }
  std::fprintf(log_, "# %s run %s --out %s --threads %d --checkpoint-every %d --resume\n", exe.c_str(),
               s.scene.c_str(), s.out_dir.c_str(), threads, checkpoint_every);
}

SceneProcess::~SceneProcess() {
  if (fd_ >= 0) ::close(fd_);
  if (log_) std::fclose(log_);
  if (pid_ > 0) {  // only when finish was never reached (an exception): do not leave a zombie or an orphan
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
}

bool SceneProcess::read_some() {
  char buf[4096];
  const ssize_t n = ::read(fd_, buf, sizeof buf);
  if (n < 0 && errno == EINTR) return true;
  if (n <= 0) {
    if (!pending_.empty()) take_line(pending_);
    pending_.clear();
    return false;
  }
  std::fwrite(buf, 1, std::size_t(n), log_);
  pending_.append(buf, std::size_t(n));
  std::size_t nl;
  while ((nl = pending_.find('\n')) != std::string::npos) {
    take_line(pending_.substr(0, nl));
    pending_.erase(0, nl + 1);
  }
  return true;
}

// Progress lines of `clothsim run` off a terminal read "frame 0012  12/48  ..." (tools/progress.cpp).
void SceneProcess::take_line(const std::string& line) {
  int frame = 0, done = 0, total = 0;
  if (std::sscanf(line.c_str(), "frame %d %d/%d", &frame, &done, &total) == 3) {
    frames_done_ = done;
    return;
  }
  const std::string tag = "clothsim: error: ";
  const auto at = line.find("error: ");
  if (line.rfind(tag, 0) == 0) error_ = line.substr(tag.size());
  else if (at != std::string::npos && error_.empty()) error_ = line.substr(at + 7);
}

void SceneProcess::finish(BatchScene& s) {
  while (read_some()) {
  }
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  s.frames = frames_done_;
  s.message = error_;
  if (WIFSIGNALED(status)) {
    s.exit_code = 128 + WTERMSIG(status);
    s.status = "crashed";
    s.message = std::string("killed by signal ") + std::to_string(WTERMSIG(status)) + " (" +
                strsignal(WTERMSIG(status)) + "); see " + s.out_dir + "/run.log";
    return;
  }
  s.exit_code = WEXITSTATUS(status);
  s.status = s.exit_code == 0 ? "ok" : s.exit_code == 2 ? "bad input" : s.exit_code == 3 ? "diverged" : "failed";
  if (s.exit_code == 0) {
    s.frames = s.total_frames;
    io::write_file_atomic(batch_done_marker(s), marker_text(s) + std::to_string(s.frames) + " frames\n");
  }
}

}  // namespace clothsim::cli
