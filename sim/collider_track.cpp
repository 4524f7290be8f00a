#include "sim/collider_track.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "core/transform.h"
#include "io/collider_reader.h"

namespace clothsim::sim {

void ColliderTrack::prepare(const Model& m, int frame, CollisionScratch& s) const {
  const CollisionModel& c = m.collision;
  if (!c.animated) return;
  if (!present_) throw std::logic_error("a model with animated colliders needs its scene to stream their frames");
  for (std::size_t k = 0; k < c.colliders.size(); ++k) {
    const ColliderInfo& ci = c.colliders[k];
    if (ci.shape != ColliderShape::sequence) continue;
    ColliderWindow& w = s.collider_frames[k];
    // The steps of this frame blend stored frames from the previous frame's to this one's, and read the next one
    // at weight 0 at the frame's end (frame_blend clamps at the sequence's ends). One more frame back covers a
    // step start that summed step lengths put a rounding error before the previous frame.
    const auto clamp = [&](int f) { return std::clamp(f, 0, ci.frame_count - 1); };
    const int lo = clamp(frame - 2 - ci.first_frame), hi = clamp(frame + 1 - ci.first_frame);
    if (w.holds(lo) && w.holds(hi)) continue;
    const std::size_t nv = std::size_t(ci.vertex_end - ci.vertex_begin);
    // Keep the frames the new window shares with the old (a run goes forward: they sit at its end), read the rest.
    const int count = std::min(collider_window_frames, ci.frame_count - lo);
    int kept = 0;  // the new window's first frames, already held
    if (w.count > 0 && lo >= w.first && lo < w.first + w.count) {
      const int shift = lo - w.first;
      kept = std::min(w.first + w.count - lo, count);
      std::copy(w.x.begin() + std::ptrdiff_t(shift * nv), w.x.begin() + std::ptrdiff_t((shift + kept) * nv), w.x.begin());
    }
    for (int j = kept; j < count; ++j) {
      const MeshData mesh = io::read_collider_frame(scene_, k, ci.first_frame + lo + j);
      if (std::size_t(mesh.vertex_count()) != nv)
        throw Error(mesh.source, "collider '" + ci.name + "': frame has " + std::to_string(mesh.vertex_count()) +
                                     " vertices; expected " + std::to_string(nv) + " like its first frame");
      const ColliderDesc& d = scene_.colliders[k];
      for (std::size_t i = 0; i < nv; ++i) w.x[std::size_t(j) * nv + i] = apply_transform(d.transform, mesh.positions[i]);
    }
    w.first = lo;
    w.count = count;
  }
}

}  // namespace clothsim::sim
