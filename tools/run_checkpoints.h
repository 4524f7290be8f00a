#pragma once
// Checkpointing and --resume for `clothsim run`, kept out of the run loop: the loop asks where to start and
// reports each frame it wrote.
#include <cstdint>
#include <optional>
#include <string>

#include "core/model.h"
#include "core/scene_desc.h"

namespace clothsim::cli {

class RunCheckpoints {
 public:
  // every: frames between checkpoints (0: none). Checkpoints go to `dir` as <scene stem>.<frame>.ckpt.
  // inputs: io::inputs_fingerprint of the scene; first_output: the first frame this run writes.
  RunCheckpoints(const SceneDesc& scene, std::uint64_t inputs, const Model& model, const SimOptions& options,
                 const State& initial, std::string dir, int every, int first_output);

  // Where the run starts: with `resume`, the newest valid checkpoint (warning on stderr about each invalid newer
  // one): its state and the first frame still to compute; otherwise, or when none is valid, no state and
  // options.start_frame. When resuming or checkpointing, checkpoints after the starting point are deleted: this run
  // replaces them.
  struct Start {
    int first_frame = 0;
    std::optional<State> state;  // the checkpoint's state at first_frame - 1, when resuming from one
    CholeskyRenewal cholesky_renewal;  // and the Cholesky preconditioner's renewal run then
  };
  Start start(bool resume, bool quiet);

  // Called after `frame`'s output is written; writes a checkpoint every `every` frames and at `last_frame`.
  void frame_written(int frame, int last_frame, const State& state, const CholeskyRenewal& renewal);

 private:
  std::string dir_, stem_;
  int every_, start_frame_, first_output_;
  std::uint64_t fingerprint_;
  Index particle_count_;
};

}  // namespace clothsim::cli
