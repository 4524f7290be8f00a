#include "systems/collision/broad_phase.h"

#include <tbb/parallel_reduce.h>

namespace clothsim {

void build_broad_phase(const Model& m, const State& in, const State& out, CollisionScratch& s) {
  const CollisionModel& c = m.collision;
  const Real inflate = c.max_thickness;
  parallel_over(Index(c.prim.size()), 1024, [&](Index slot) {
    const PrimCorners t = corners(m, in, out, s, c.prim[slot]);
    Aabb b = swept_box(t.x0[0], t.x1[0]);
    for (int k = 1; k < 3; ++k) { grow(b, t.x0[k]); grow(b, t.x1[k]); }
    b.lo.array() -= inflate;
    b.hi.array() += inflate;
    s.prim_box[slot] = b;
  });
  // Bounds of every cloth vertex's swept box: min/max are exact, so the reduction order does not matter.
  s.query_bounds = tbb::parallel_reduce(
      tbb::blocked_range<Index>(0, m.particle_count, particle_grain),
      Aabb{Vec3::Constant(1e300), Vec3::Constant(-1e300)},
      [&](const tbb::blocked_range<Index>& r, Aabb b) {
        for (Index i = r.begin(); i != r.end(); ++i) { grow(b, in.x[i]); grow(b, out.x[i]); }
        return b;
      },
      [](Aabb a, const Aabb& b) { grow(a, b.lo); grow(a, b.hi); return a; });
  if (c.broad_phase == BroadPhase::bvh) refit_bvh(c, s);
  else build_spatial_hash(c, s);
}

}  // namespace clothsim
