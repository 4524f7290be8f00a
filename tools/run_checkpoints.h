#pragma once
// Checkpointing and --resume for `clothsim run`, kept out of the run loop: the loop asks where to start and
// reports each frame it wrote.
#include <cstdint>
#include <string>

#include "core/model.h"
#include "core/scene_desc.h"

namespace clothsim::cli {

class RunCheckpoints {
 public:
  // every: frames between checkpoints (0: none). Checkpoints go to `dir` as <scene stem>.<frame>.ckpt.
  // inputs: io::inputs_fingerprint of the scene; first_output: the first frame this run writes.
  RunCheckpoints(const SceneDesc& scene, std::uint64_t inputs, const Model& model, const State& initial,
                 std::string dir, int every, int first_output);

  // With `resume`, loads the newest valid checkpoint into `state` (warning on stderr about each invalid newer
  // one) and returns the first frame still to compute; otherwise, or when none is valid, model.start_frame.
  // When resuming or checkpointing, checkpoints after the starting point are deleted: this run replaces them.
  int start(bool resume, State& state, bool quiet);

  // Called after `frame`'s output is written; writes a checkpoint every `every` frames and at `last_frame`.
  void frame_written(int frame, int last_frame, const State& state);

 private:
  std::string dir_, stem_;
  int every_, start_frame_, first_output_;
  std::uint64_t fingerprint_;
  Index particle_count_;
};

}  // namespace clothsim::cli
