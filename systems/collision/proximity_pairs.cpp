#include "systems/collision/proximity_pairs.h"

#include "systems/collision/response.h"

namespace clothsim {

void respond_proximities(const Model& m, const State& in, const State& out, CollisionScratch& s, BroadMode mode,
                         Real h) {
  for_each_proximity(
      m, in, out, s, mode,
      [&](Index i, Index prim, const PrimCorners& t, const TriangleProximity& px, Real d) {
        if (!t.cloth && m.particle_inv_mass[i] == 0) return;
        respond_vertex_triangle(m, out, s, i, prim, t, px.w, px.n, d, h, false);
      },
      [&](Index e, Index f, const EdgeProximity& px, Real d) { respond_cloth_edges(m, out, s, e, f, px, d, h); },
      [&](Index t, Index v, const TriangleProximity& px, const Vec3& n, Real d) {
        respond_collider_vertex(m, out, s, t, v, px, n, d, h);
      },
      [&](Index e, Index g, const EdgeProximity& px, Real d) { respond_collider_edge(m, out, s, e, g, px, d, h); });
}

}  // namespace clothsim
