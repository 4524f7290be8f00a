#include "tools/run_checkpoints.h"

#include <cstdio>
#include <filesystem>
#include <vector>

#include "io/checkpoint.h"

namespace clothsim::cli {

RunCheckpoints::RunCheckpoints(const SceneDesc& scene, std::uint64_t inputs, const Model& model,
                               const SimOptions& options, const State& initial, std::string dir, int every,
                               int first_output)
    : dir_(std::move(dir)),
      stem_(std::filesystem::path(scene.path).stem().string()),
      every_(every),
      start_frame_(options.start_frame),
      first_output_(first_output),
      fingerprint_(io::scene_fingerprint(inputs, options.dt, initial.x)),
      particle_count_(model.particle_count) {}

RunCheckpoints::Start RunCheckpoints::start(bool resume, bool quiet) {
  Start at{start_frame_, std::nullopt};
  if (resume) {
    std::vector<std::string> warnings;
    auto c = io::find_latest_checkpoint(dir_, stem_, fingerprint_, particle_count_, first_output_, warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "clothsim: warning: %s\n", w.c_str());
    if (c) {
      at.state = std::move(c->state);
      at.cholesky_renewal = c->cholesky_renewal;
      at.first_frame = c->frame + 1;
      first_output_ = c->first_output;  // the frames before this run's were written by the checkpoint's run
      if (!quiet) std::fprintf(stderr, "clothsim: resuming after frame %d from its checkpoint\n", c->frame);
    } else {
      std::fprintf(stderr, "clothsim: warning: no valid checkpoint in %s; starting from frame %d\n",
                   dir_.c_str(), start_frame_);
    }
  }
  // Newer checkpoints describe frames this run replaces; a run that neither checkpoints nor resumes leaves
  // them alone.
  if (resume || every_ > 0) io::remove_checkpoints_after(dir_, stem_, at.first_frame - 1);
  return at;
}

void RunCheckpoints::frame_written(int frame, int last_frame, const State& state, const CholeskyRenewal& renewal) {
  if (every_ <= 0 || ((frame - start_frame_) % every_ != 0 && frame != last_frame)) return;
  io::Checkpoint c;
  c.fingerprint = fingerprint_;
  c.frame = frame;
  c.first_output = first_output_;
  c.state = state;
  c.cholesky_renewal = renewal;
  io::write_checkpoint(dir_, stem_, c);
}

}  // namespace clothsim::cli
