#pragma once
// The animated colliders' frames, streamed (DESIGN.md: collider tracks, a few frames ahead, never all): before the
// steps of a frame, each sequence collider's window (core/collision_model.h, ColliderWindow) holds the frames those
// steps blend, read from disk as the run reaches them. Memory stays at collider_window_frames frames a collider
// whatever the sequence's length; load_scene has read and checked every frame once.
#include <vector>

#include "core/model.h"
#include "core/scene_desc.h"

namespace clothsim::sim {

class ColliderTrack {
 public:
  ColliderTrack() = default;  // a scene without animated colliders
  explicit ColliderTrack(const SceneDesc& scene) : scene_(scene), present_(true) {}

  // Makes every sequence collider's window in s hold the frames the steps from frame - 1 to frame read. Throws
  // Error naming a frame file that can no longer be read or no longer matches the first frame, and
  // std::logic_error when the model has animated colliders but this track has no scene.
  void prepare(const Model& model, int frame, CollisionScratch& s) const;

 private:
  SceneDesc scene_;
  bool present_ = false;
};

}  // namespace clothsim::sim
