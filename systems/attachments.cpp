#include "systems/attachments.h"

#include "core/attachments.h"
#include "systems/parallel.h"

namespace clothsim {

void apply_attachments(const Model& m, const CollisionScratch& s, const State& in, State& out, Real h) {
  const Index n = Index(m.attach_particle.size());
  if (n == 0) return;
  const CollisionModel& c = m.collision;
  // The end of the step at the time place_colliders (systems/collision/colliders.h) gives the colliders: the same
  // vertices.
  const Real t = in.time + h;
  parallel_over(n, particle_grain, [&](Index k) {
    const ColliderInfo& ci = c.colliders[m.attach_collider[k]];
    const FrameBlend b = frame_blend(ci, t);
    const Index* v = &c.mesh_tri_index[3 * m.attach_tri[k]];
    const ColliderWindow& w = s.collider_frames[m.attach_collider[k]];
    const Vec3 p = attachment_point(m.attach_weight[k], m.attach_offset[k], collider_vertex(c, ci, w, b, v[0]),
                                    collider_vertex(c, ci, w, b, v[1]), collider_vertex(c, ci, w, b, v[2]));
    const Index i = m.attach_particle[k];
    out.v[i] = (p - in.x[i]) / h;
    out.x[i] = p;
  });
}

}  // namespace clothsim
