#include "systems/collision/continuous_pairs.h"

namespace clothsim {

std::int64_t collide_continuous(const Model& m, const State& in, State& out, CollisionScratch& s, BroadMode mode,
                                Real h) {
  clear_accumulators(m, s);
  for_each_crossing(
      m, in, out, s, mode, [](const Index*, int) { return true; },
      [&](Index i, Index prim, const PrimCorners& t, const Real* w, const Vec3& n, Real d) {
        respond_vertex_triangle(m, out, s, i, prim, t, w, n, d, h, true);
      },
      [&](Index t, Index v, const Real* w, const Vec3& n, Real d) {
        respond_collider_vertex_crossing(m, out, s, t, v, w, n, d, h);
      },
      [&](const Index* p, bool fixed, const Vec3* x0, const Vec3* x1, const EdgeProximity& px, const Vec3& n, Real d,
          Real mu) { respond_edge_crossing(m, out, s, p, fixed, x0, x1, px, n, d, mu, h); });
  return apply_accumulated(m, out, s);
}

}  // namespace clothsim
