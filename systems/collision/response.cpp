#include "systems/collision/response.h"

#include <tbb/parallel_reduce.h>

#include "systems/collision/broad_phase.h"
#include "systems/collision/proximity_pairs.h"
#include "systems/parallel.h"

namespace clothsim {

void clear_accumulators(const Model& m, CollisionScratch& s) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    s.acc_count[i] = 0;
    for (int k = 0; k < 3; ++k) s.acc_dv[3 * std::size_t(i) + k] = s.acc_dx[3 * std::size_t(i) + k] = 0;
  });
}

std::int64_t apply_accumulated(const Model& m, State& out, CollisionScratch& s) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    const std::int32_t n = s.acc_count[i];
    if (n == 0) return;
    const Real scale = 1.0 / (fixed_scale * n);
    for (int k = 0; k < 3; ++k) {
      out.v[i][k] += Real(s.acc_dv[3 * std::size_t(i) + k]) * scale;
      out.x[i][k] += Real(s.acc_dx[3 * std::size_t(i) + k]) * scale;
    }
  });
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<Index>(0, m.particle_count, particle_grain), std::int64_t(0),
      [&](const tbb::blocked_range<Index>& r, std::int64_t sum) {
        for (Index i = r.begin(); i != r.end(); ++i) sum += s.acc_count[i];
        return sum;
      },
      [](std::int64_t a, std::int64_t b) { return a + b; });
}

// The point gets the vertex-collider response (restitution, Coulomb friction, the push to the thickness), spread
// over its particles by w_k inv_m_k / sum w^2 inv_m so that the point itself changes by exactly that.
void respond_collider_point(const Model& m, const State& out, CollisionScratch& s, const Index* p, const Real* w,
                            int count, const Vec3& c0, const Vec3& c1, const Vec3& n, Real d, Real thick, Real mu,
                            Real h) {
  Vec3 u = Vec3::Zero();
  Real denom = 0;
  weighted_velocity(p, w, count, m, out.v, u, denom);
  if (!(denom > 0)) return;
  const Real e = m.cloths[m.collision.particle_cloth[p[0]]].restitution;
  const Vec3 dv = collider_velocity_change(u, (c1 - c0) / h, n, e, mu);
  const Vec3 dx = collider_position_change(dv, n, d, thick, h);
  for (int k = 0; k < count; ++k) {
    const Real share = w[k] * m.particle_inv_mass[p[k]] / denom;
    accumulate_contact(s, p[k], share * dv, share * dx);
    if (w[k] > 0) note_collider_contact(s, p[k], n, (c1 - c0) / h, mu);
  }
}

void respond_vertex_triangle(const Model& m, const State& out, CollisionScratch& s, Index i, Index prim,
                             const PrimCorners& t, const Real* w, const Vec3& n, Real d, Real h, bool crossed) {
  const Real thick = m.particle_thickness[i];
  const Real mu = contact_friction(m, i, prim);
  if (!t.cloth) {
    const Vec3 v_col = prim_velocity(t, w, h);
    note_collider_contact(s, i, n, v_col, mu);
    if (d >= thick) return;  // within collider_reach only: held in the next solve, not pushed
    const Vec3 dv = collider_velocity_change(out.v[i], v_col, n, m.cloths[m.collision.particle_cloth[i]].restitution,
                                             mu);
    accumulate_contact(s, i, dv, eased_position_change(dv, n, d, thick, h));
    return;
  }
  const Index p[4] = {i, t.p[0], t.p[1], t.p[2]};
  const Real wt[4] = {1, -w[0], -w[1], -w[2]};
  Vec3 dv[4], dx[4];
  if (crossed) {
    if (!inelastic_separation(p, wt, 4, m, out.v, Vec3::Zero(), n, d, thick, mu, h, dv, dx)) return;
  } else {
    if (!cloth_impulse(p, wt, 4, m, out.v, n, d, thick, mu, h, dv)) return;
    for (int k = 0; k < 4; ++k) dx[k] = h * dv[k];
  }
  for (int k = 0; k < 4; ++k) accumulate_contact(s, p[k], dv[k], dx[k]);
}

void respond_cloth_edges(const Model& m, const State& out, CollisionScratch& s, Index e, Index f,
                         const EdgeProximity& px, Real d, Real h) {
  const CollisionModel& c = m.collision;
  const Index p[4] = {c.edge_a[e], c.edge_b[e], c.edge_a[f], c.edge_b[f]};
  const Real wt[4] = {1 - px.s, px.s, -(1 - px.t), -px.t};
  const Real mu = cloth_pair_friction(m, p[0], p[2]);
  Vec3 dv[4];
  const Real thick = edge_pair_thickness(m, p, false, px.s, px.t);
  if (!cloth_impulse(p, wt, 4, m, out.v, px.n, d, thick, mu, h, dv)) return;
  for (int k = 0; k < 4; ++k) accumulate_contact(s, p[k], dv[k], h * dv[k]);
}

void respond_collider_vertex(const Model& m, const State& out, CollisionScratch& s, Index t, Index v,
                             const TriangleProximity& px, const Vec3& n, Real d, Real h) {
  const CollisionModel& c = m.collision;
  const Index* p = &m.tri_index[3 * t];
  const Real mu = collider_friction(m, p[0], c.mesh_tri_collider[c.mesh_vertex_first_tri[v]]);
  respond_collider_point(m, out, s, p, px.w, 3, s.collider_x0[v], s.collider_x1[v], n, d, triangle_thickness(m, p),
                         mu, h);
}

void respond_collider_edge(const Model& m, const State& out, CollisionScratch& s, Index e, Index g,
                           const EdgeProximity& px, Real d, Real h) {
  const CollisionModel& c = m.collision;
  const Index p[2] = {c.edge_a[e], c.edge_b[e]};
  const Real w[2] = {1 - px.s, px.s};
  const Index ga = c.mesh_edge_a[g], gb = c.mesh_edge_b[g];
  const Vec3 c0 = (1 - px.t) * s.collider_x0[ga] + px.t * s.collider_x0[gb];
  const Vec3 c1 = (1 - px.t) * s.collider_x1[ga] + px.t * s.collider_x1[gb];
  const Real mu = collider_friction(m, p[0], c.mesh_tri_collider[c.mesh_edge_first_tri[g]]);
  const Real thick = edge_thickness_at(m, p[0], p[1], px.s);
  respond_collider_point(m, out, s, p, w, 2, c0, c1, px.n, d, thick, mu, h);
}

void respond_collider_vertex_crossing(const Model& m, const State& out, CollisionScratch& s, Index t, Index v,
                                      const Real* w, const Vec3& n, Real d, Real h) {
  const CollisionModel& c = m.collision;
  const Index* p = &m.tri_index[3 * t];
  const Real mu = collider_friction(m, p[0], c.mesh_tri_collider[c.mesh_vertex_first_tri[v]]);
  const Vec3 v_col = (s.collider_x1[v] - s.collider_x0[v]) / h;
  Vec3 dv[3], dx[3];
  if (!inelastic_separation(p, w, 3, m, out.v, v_col, n, d, triangle_thickness(m, p), mu, h, dv, dx)) return;
  for (int k = 0; k < 3; ++k) accumulate_contact(s, p[k], dv[k], dx[k]);
}

void respond_edge_crossing(const Model& m, const State& out, CollisionScratch& s, const Index* p, bool fixed,
                           const Vec3* x0, const Vec3* x1, const EdgeProximity& px, const Vec3& n, Real d, Real mu,
                           Real h) {
  const Real wt[4] = {1 - px.s, px.s, -(1 - px.t), -px.t};
  const int count = fixed ? 2 : 4;
  Vec3 v_fixed = Vec3::Zero();
  if (fixed) v_fixed = ((1 - px.t) * (x1[2] - x0[2]) + px.t * (x1[3] - x0[3])) / h;
  Vec3 dv[4], dx[4];
  const Real thick = edge_pair_thickness(m, p, fixed, px.s, px.t);
  if (!inelastic_separation(p, wt, count, m, out.v, v_fixed, n, d, thick, mu, h, dv, dx)) return;
  for (int k = 0; k < count; ++k) accumulate_contact(s, p[k], dv[k], dx[k]);
}

}  // namespace clothsim
