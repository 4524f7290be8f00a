#include "systems/collision/broad_phase.h"

#include "systems/collision/response.h"

#include <tbb/parallel_reduce.h>

namespace clothsim {

namespace {
// Swept, thickness-inflated boxes of slots [begin, end).
void prim_boxes(const Model& m, const State& in, const State& out, CollisionScratch& s, Index begin, Index end) {
  const CollisionModel& c = m.collision;
  parallel_over(end - begin, 1024, [&](Index k) {
    const Index slot = begin + k;
    // A collider's triangles reach as far as the contact filter's holds (systems/collision/response.h).
    const Real inflate = slot < c.cloth_prim_count ? c.max_thickness : collider_reach(s, c.max_thickness);
    const PrimCorners t = corners(m, in, out, s, c.prim[slot]);
    Aabb b = swept_box(t.x0[0], t.x1[0]);
    for (int j = 1; j < 3; ++j) { grow(b, t.x0[j]); grow(b, t.x1[j]); }
    b.lo.array() -= inflate;
    b.hi.array() += inflate;
    s.prim_box[slot] = b;
  });
}
}  // namespace

void build_cloth_broad_phase(const Model& m, const State& in, const State& out, CollisionScratch& s) {
  const CollisionModel& c = m.collision;
  prim_boxes(m, in, out, s, 0, c.cloth_prim_count);
  // Bounds of every cloth vertex's swept box: min/max are exact, so the reduction order does not matter.
  s.query_bounds = tbb::parallel_reduce(
      tbb::blocked_range<Index>(0, m.particle_count, particle_grain),
      Aabb{Vec3::Constant(1e300), Vec3::Constant(-1e300)},
      [&](const tbb::blocked_range<Index>& r, Aabb b) {
        for (Index i = r.begin(); i != r.end(); ++i) { grow(b, in.x[i]); grow(b, out.x[i]); }
        return b;
      },
      [](Aabb a, const Aabb& b) { grow(a, b.lo); grow(a, b.hi); return a; });
  note_cloth_boxes(m, in, out, s);
  if (c.broad_phase == BroadPhase::bvh) refit_bvh(c.cloth_tree, s.prim_box, s.cloth_node_box);
  else build_spatial_hash(c, s);
}

void build_broad_phase(const Model& m, const State& in, const State& out, CollisionScratch& s) {
  const CollisionModel& c = m.collision;
  drop_candidate_lists(s);
  prim_boxes(m, in, out, s, c.cloth_prim_count, Index(c.prim.size()));
  refit_bvh(c.collider_tree, s.prim_box, s.collider_node_box);
  build_cloth_broad_phase(m, in, out, s);
}

}  // namespace clothsim
