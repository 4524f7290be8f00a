#include "systems/collision/colliders.h"

#include "systems/collision/response.h"
#include "systems/parallel.h"

namespace clothsim {

void place_colliders(const Model& m, Real time, Real h, CollisionScratch& s) {
  const CollisionModel& c = m.collision;
  if (!c.animated) return;
  // The step's own start time: with timestep="auto" the steps of a frame differ in length, so a step count
  // times h would place the body at the wrong time.
  auto at = [&](const ColliderInfo& ci, const ColliderWindow& w, Real t, std::vector<Vec3>& dst) {
    const FrameBlend b = frame_blend(ci, t);
    parallel_over(ci.vertex_end - ci.vertex_begin, particle_grain,
                  [&](Index k) { dst[ci.vertex_begin + k] = collider_vertex(c, ci, w, b, ci.vertex_begin + k); });
  };
  for (std::size_t k = 0; k < c.colliders.size(); ++k) {
    const ColliderInfo& ci = c.colliders[k];
    if (ci.shape != ColliderShape::sequence) continue;
    at(ci, s.collider_frames[k], time, s.collider_x0);
    at(ci, s.collider_frames[k], time + h, s.collider_x1);
  }
}

// Spheres and planes: exact signed distances, tested against every particle (no broad phase needed).
void collide_analytic(const Model& m, State& out, CollisionScratch& s, Real h) {
  const CollisionModel& c = m.collision;
  bool any = false;
  for (const ColliderInfo& ci : c.colliders)
    any = any || ci.shape == ColliderShape::sphere || ci.shape == ColliderShape::plane;
  if (!any) return;
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    if (m.particle_inv_mass[i] == 0) return;
    const ClothInfo& cloth = m.cloths[c.particle_cloth[i]];
    const Real thick = m.particle_thickness[i];
    for (const ColliderInfo& ci : c.colliders) {
      Vec3 n;
      Real d;
      if (ci.shape == ColliderShape::sphere) {
        const Vec3 r = out.x[i] - ci.center;
        const Real len = r.norm();
        n = len > 0 ? Vec3(r / len) : Vec3(0, 1, 0);
        d = len - ci.radius;
      } else if (ci.shape == ColliderShape::plane) {
        n = ci.normal;
        d = n.dot(out.x[i] - ci.point);
      } else {
        continue;
      }
      if (d >= collider_reach(s, thick)) continue;
      const Real mu = combine_friction(cloth.friction, ci.friction);
      note_collider_contact(s, i, n, Vec3::Zero(), mu);
      if (d >= thick) continue;  // within collider_reach only: held in the next solve, not pushed
      const Vec3 dv = collider_velocity_change(out.v[i], Vec3::Zero(), n, cloth.restitution, mu);
      accumulate_contact(s, i, dv, eased_position_change(dv, n, d, thick, h));
    }
  });
}

}  // namespace clothsim
