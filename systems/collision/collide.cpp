#include "systems/collision/collide.h"

#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>

#include "systems/collision/bvh.h"
#include "systems/collision/ccd.h"
#include "systems/collision/response.h"
#include "systems/collision/impact_zones.h"
#include "systems/parallel.h"
#include "systems/collision/proximity.h"
#include "systems/collision/push_out.h"
#include "systems/collision/spatial_hash.h"

namespace clothsim {
namespace {

inline constexpr Index contact_grain = 256;

Aabb swept_box(const Vec3& a0, const Vec3& a1) { return {a0.cwiseMin(a1), a0.cwiseMax(a1)}; }
void grow(Aabb& b, const Vec3& p) { b.lo = b.lo.cwiseMin(p); b.hi = b.hi.cwiseMax(p); }

template <class Visit>
void for_each_candidate(const Model& m, const CollisionScratch& s, BroadMode mode, const Aabb& q, Visit&& visit) {
  switch (mode) {
    case BroadMode::hash: query_spatial_hash(s, q, visit); break;
    case BroadMode::bvh: query_bvh(m.collision, s, q, visit); break;
    case BroadMode::brute:
      for (Index slot = 0; slot < Index(m.collision.prim.size()); ++slot)
        if (boxes_overlap(q, s.prim_box[slot])) visit(slot);
      break;
  }
}

// Corners of a broad-phase prim at the start and end of the step.
struct PrimCorners {
  Index p[3];
  Vec3 x0[3], x1[3];
  bool cloth;
};
PrimCorners corners(const Model& m, const State& in, const State& out, const CollisionScratch& s, Index prim) {
  PrimCorners c;
  c.cloth = prim < m.tri_count;
  for (int k = 0; k < 3; ++k) {
    if (c.cloth) {
      c.p[k] = m.tri_index[3 * prim + k];
      c.x0[k] = in.x[c.p[k]];
      c.x1[k] = out.x[c.p[k]];
    } else {
      c.p[k] = m.collision.mesh_tri_index[3 * (prim - m.tri_count) + k];
      c.x0[k] = s.collider_x0[c.p[k]];
      c.x1[k] = s.collider_x1[c.p[k]];
    }
  }
  return c;
}

// Outward direction at collider vertex v at the end of the step: the sum of its triangles' normals (area
// weighted, not normalised), gathered in triangle order.
Vec3 collider_vertex_normal(const CollisionModel& c, const CollisionScratch& s, Index v) {
  Vec3 n = Vec3::Zero();
  for (Index k = c.mesh_vertex_tri_offset[v]; k < c.mesh_vertex_tri_offset[v + 1]; ++k) {
    const Index* t = &c.mesh_tri_index[3 * c.mesh_vertex_tri[k]];
    n += (s.collider_x1[t[1]] - s.collider_x1[t[0]]).cross(s.collider_x1[t[2]] - s.collider_x1[t[0]]);
  }
  return n;
}

// Which way along the cloth triangle's unit normal nt the triangle must lie from a collider vertex: the
// collider's outside, by the vertex's outward direction nv (collider meshes are one-sided: their normals point
// out), where that decides (|cos| > 0.2), so that a triangle already pushed past the vertex is sent back out;
// otherwise (a triangle edge-on to the surface) the side it lay on at the start of the step, from
// start = nt0 . (vertex - corner) at the start (the vertex's side of the triangle).
Real collider_vertex_side(const Vec3& nt, const Vec3& nv, Real start) {
  const Real cos = nt.dot(nv);
  if (std::abs(cos) > 0.2 * nv.norm()) return cos > 0 ? 1 : -1;
  return start > 0 ? -1 : 1;
}

Real triangle_thickness(const Model& m, const Index* p) {
  return std::max({m.particle_thickness[p[0]], m.particle_thickness[p[1]], m.particle_thickness[p[2]]});
}

// Edge-edge contacts: each cloth edge's thickness interpolated between its ends at the closest point (s on
// p[0]p[1], t on p[2]p[3]; a collider edge, `fixed`, has none), the larger of the two sides, so the contact
// does not depend on which edge is numbered first. edge_pair_reach bounds it for the detection tests.
Real edge_pair_reach(const Model& m, const Index* p, bool fixed) {
  const Real own = std::max(m.particle_thickness[p[0]], m.particle_thickness[p[1]]);
  return fixed ? own : std::max({own, m.particle_thickness[p[2]], m.particle_thickness[p[3]]});
}
Real edge_thickness_at(const Model& m, Index a, Index b, Real s) {
  const Real ha = m.particle_thickness[a];
  return ha + s * (m.particle_thickness[b] - ha);  // exactly ha when both ends agree
}
Real edge_pair_thickness(const Model& m, const Index* p, bool fixed, Real s, Real t) {
  const Real own = edge_thickness_at(m, p[0], p[1], s);
  return fixed ? own : std::max(own, edge_thickness_at(m, p[2], p[3], t));
}

// Every collider-mesh vertex whose swept box may come within the thickness of cloth triangle t's swept box,
// through the broad phase's collider triangles: a vertex is reported only by its lowest triangle, so each
// (t, vertex) pair once. on_pair(t, vertex). Nothing for a scene without collider meshes.
template <class OnPair>
void for_each_collider_vertex_pair(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                                   BroadMode mode, OnPair&& on_pair) {
  const CollisionModel& c = m.collision;
  if (c.mesh_vertex_first_tri.empty()) return;
  parallel_over(m.tri_count, contact_grain, [&](Index t) {
    const Index* p = &m.tri_index[3 * t];
    if (m.particle_inv_mass[p[0]] == 0 && m.particle_inv_mass[p[1]] == 0 && m.particle_inv_mass[p[2]] == 0) return;
    Aabb q = swept_box(in.x[p[0]], out.x[p[0]]);
    for (int k = 1; k < 3; ++k) { grow(q, in.x[p[k]]); grow(q, out.x[p[k]]); }
    for_each_candidate(m, s, mode, q, [&](Index slot) {
      const Index prim = c.prim[slot];
      if (prim < m.tri_count) return;
      const Index tri = prim - m.tri_count;
      for (int k = 0; k < 3; ++k) {
        const Index v = c.mesh_tri_index[3 * tri + k];
        if (c.mesh_vertex_first_tri[v] == tri) on_pair(t, v);
      }
    });
  });
}

// Outward direction at collider edge g at the end of the step: the sum of its end vertices' outward directions
// (not normalised).
Vec3 collider_edge_normal(const CollisionModel& c, const CollisionScratch& s, Index g) {
  return collider_vertex_normal(c, s, c.mesh_edge_a[g]) + collider_vertex_normal(c, s, c.mesh_edge_b[g]);
}

// The side a cloth edge near collider edge g must keep, as for a cloth triangle near a collider vertex
// (collider_vertex_side): the collider's outside, by the edge's outward direction nv, where that decides
// (|cos| > 0.2), so that a cloth edge already through a body edge is sent back out; otherwise the side it came
// from, as edge_pair_proximity left it. px.n (from the collider edge to the cloth edge) and the signed distance
// d are turned to that side.
void collider_edge_side(const Vec3& nv, EdgeProximity& px, Real& d) {
  const Vec3 towards = d < 0 ? Vec3(-px.n) : px.n;  // where the cloth edge lies from the collider's at the end
  const Real cos = towards.dot(nv);
  if (std::abs(cos) <= 0.2 * nv.norm()) return;
  const Real distance = std::abs(d);
  px.n = cos > 0 ? towards : Vec3(-towards);
  d = cos > 0 ? distance : -distance;
}

// Edge x[0]x[1] against edge x[2]x[3] at the end of the step (x1; x0 at its start; pointers, so a pair the
// boxes reject reads no start position): the closest points within the thickness h, pointed back to the side the
// first edge came from when the pair crossed during the step. False when apart.
bool edge_pair_proximity(const Vec3* const x0[4], const Vec3* const x1[4], Real h, EdgeProximity& px, Real& d) {
  // Cheap reject before the closest points: the end-of-step boxes must come within h.
  const Aabb ea = swept_box(*x1[0], *x1[1]), eb = swept_box(*x1[2], *x1[3]);
  if (((ea.lo.array() - h) > eb.hi.array()).any() || ((eb.lo.array() - h) > ea.hi.array()).any()) return false;
  if (!edge_edge_proximity(*x1[0], *x1[1], *x1[2], *x1[3], px) || px.d >= h) return false;
  EdgeProximity start;
  d = px.d;
  if (edge_edge_proximity(*x0[0], *x0[1], *x0[2], *x0[3], start) && start.n.dot(px.n) < 0) {
    px.n = start.n;  // crossed during the step: push back to the side it came from
    d = -px.d;
  }
  return true;
}

// Vertex-triangle and edge-edge proximities of the configuration out (sides taken from in), through one broad
// phase. on_vertex(i, prim, corners, proximity, d) gets d signed: negative when i crossed to the wrong side;
// on_edge(e, f, proximity, d) likewise. Against collider meshes also: on_collider_vertex(t, v, proximity, n, d),
// collider vertex v within the thickness of cloth triangle t, n the unit direction from the vertex to the side
// the triangle must keep, d the triangle's signed distance along it; on_collider_edge(e, g, proximity, d),
// cloth edge e against collider edge g, px.n pointing to the cloth edge's side.
template <class OnVertex, class OnEdge, class OnColliderVertex, class OnColliderEdge>
void for_each_proximity(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                        BroadMode mode, OnVertex&& on_vertex, OnEdge&& on_edge, OnColliderVertex&& on_collider_vertex,
                        OnColliderEdge&& on_collider_edge) {
  const CollisionModel& c = m.collision;
  if (c.prim.empty()) return;
  parallel_over(m.particle_count, contact_grain, [&](Index i) {
    const Real h = m.particle_thickness[i];
    const Aabb q = swept_box(in.x[i], out.x[i]);
    const Real own_motion = (out.x[i] - in.x[i]).norm();
    for_each_candidate(m, s, mode, q, [&](Index slot) {
      const Index prim = c.prim[slot];
      const PrimCorners t = corners(m, in, out, s, prim);
      if (t.cloth && !c.vertex_meets_cloth_triangle(i, t.p)) return;
      const Vec3& p = out.x[i];
      const Vec3 tlo = t.x1[0].cwiseMin(t.x1[1]).cwiseMin(t.x1[2]), thi = t.x1[0].cwiseMax(t.x1[1]).cwiseMax(t.x1[2]);
      if (((p.array() + h + own_motion) < tlo.array()).any() || ((p.array() - h - own_motion) > thi.array()).any())
        return;
      TriangleProximity px;
      if (!vertex_triangle_proximity(out.x[i], t.x1[0], t.x1[1], t.x1[2], h, px)) return;
      // The side is the one at the start of the step (one-sided for collider meshes: their normals point out).
      Real side = 1;
      if (t.cloth) side = (t.x0[1] - t.x0[0]).cross(t.x0[2] - t.x0[0]).dot(in.x[i] - t.x0[0]) < 0 ? -1 : 1;
      const Real d = side * px.d;
      Real motion = own_motion;
      for (int k = 0; k < 3; ++k) motion = std::max(motion, own_motion + (t.x1[k] - t.x0[k]).norm());
      if (d >= h || d <= -(h + motion)) return;
      px.n *= side;
      on_vertex(i, prim, t, px, d);
    });
  });
  for_each_collider_vertex_pair(m, in, out, s, mode, [&](Index t, Index v) {
    const Index* p = &m.tri_index[3 * t];
    const Real h = triangle_thickness(m, p);
    const Vec3 &v0 = s.collider_x0[v], &v1 = s.collider_x1[v];
    TriangleProximity px;
    if (!vertex_triangle_proximity(v1, out.x[p[0]], out.x[p[1]], out.x[p[2]], h, px)) return;
    Real motion = (v1 - v0).norm(), own = 0;
    for (int k = 0; k < 3; ++k) own = std::max(own, (out.x[p[k]] - in.x[p[k]]).norm());
    motion += own;
    if (!(std::abs(px.d) < h + motion)) return;
    const Real start = (in.x[p[1]] - in.x[p[0]]).cross(in.x[p[2]] - in.x[p[0]]).dot(v0 - in.x[p[0]]);
    const Real side = collider_vertex_side(px.n, collider_vertex_normal(c, s, v), start);
    const Real d = -side * px.d;  // px.d: the vertex's height over the triangle along px.n
    if (d >= h || d <= -(h + motion)) return;
    on_collider_vertex(t, v, px, Vec3(side * px.n), d);
  });
  const bool meshes = !c.mesh_edge_a.empty();
  if (!c.cloth_contact && !meshes) return;
  parallel_over(Index(c.edge_a.size()), contact_grain, [&](Index e) {
    if (!meshes && !c.edge_contact[e]) return;
    const Index a = c.edge_a[e], b = c.edge_b[e];
    Aabb q = swept_box(in.x[a], out.x[a]);
    grow(q, in.x[b]);
    grow(q, out.x[b]);
    for_each_candidate(m, s, mode, q, [&](Index slot) {
      const Index prim = c.prim[slot];
      if (prim >= m.tri_count) {
        const Index tri = prim - m.tri_count;
        for (int k = 0; k < 3; ++k) {
          const Index g = c.mesh_tri_edge[3 * tri + k];
          if (c.mesh_edge_first_tri[g] != tri) continue;
          const Index ga = c.mesh_edge_a[g], gb = c.mesh_edge_b[g];
          const Vec3* const x0[4] = {&in.x[a], &in.x[b], &s.collider_x0[ga], &s.collider_x0[gb]};
          const Vec3* const x1[4] = {&out.x[a], &out.x[b], &s.collider_x1[ga], &s.collider_x1[gb]};
          const Index p[4] = {a, b, ga, gb};
          EdgeProximity px;
          Real d;
          if (!edge_pair_proximity(x0, x1, edge_pair_reach(m, p, true), px, d)) continue;
          if (px.d >= edge_pair_thickness(m, p, true, px.s, px.t)) continue;
          collider_edge_side(collider_edge_normal(c, s, g), px, d);
          on_collider_edge(e, g, px, d);
        }
        return;
      }
      if (!c.edge_contact[e]) return;
      for (int k = 0; k < 3; ++k) {
        const Index f = c.tri_edge[3 * prim + k];
        if (f <= e || c.edge_first_tri[f] != prim) continue;
        const Index fa = c.edge_a[f], fb = c.edge_b[f];
        if (c.edges_adjacent(a, b, fa, fb)) continue;
        if (!c.cloths_collide(c.particle_cloth[a], c.particle_cloth[fa])) continue;
        const Vec3* const x0[4] = {&in.x[a], &in.x[b], &in.x[fa], &in.x[fb]};
        const Vec3* const x1[4] = {&out.x[a], &out.x[b], &out.x[fa], &out.x[fb]};
        const Index p[4] = {a, b, fa, fb};
        EdgeProximity px;
        Real d;
        if (edge_pair_proximity(x0, x1, edge_pair_reach(m, p, false), px, d) &&
            px.d < edge_pair_thickness(m, p, false, px.s, px.t))
          on_edge(e, f, px, d);
      }
    });
  });
}

// Friction of a contact: the geometric mean of the two sides' Coulomb coefficients (Box2D's rule), so a side
// with friction 0 makes the contact frictionless and two equal sides keep their value (docs/scene-format.md,
// "Friction"). Restitution is the cloth's.
Real combine_friction(Real a, Real b) { return std::sqrt(a * b); }
Real collider_friction(const Model& m, Index i, Index collider) {
  return combine_friction(m.cloths[m.collision.particle_cloth[i]].friction, m.collision.colliders[collider].friction);
}
// Cloth particles a and b on the two sides of a cloth-cloth contact.
Real cloth_pair_friction(const Model& m, Index a, Index b) {
  const CollisionModel& c = m.collision;
  return combine_friction(m.cloths[c.particle_cloth[a]].friction, m.cloths[c.particle_cloth[b]].friction);
}
Real contact_friction(const Model& m, Index i, Index prim) {
  const CollisionModel& c = m.collision;
  if (prim >= m.tri_count) return collider_friction(m, i, c.mesh_tri_collider[prim - m.tri_count]);
  return cloth_pair_friction(m, i, m.tri_index[3 * prim]);
}

// A cloth point (weights w over the particles p: a triangle's barycentrics or an edge's) touching an immovable
// collider point that moves from c0 to c1 over the step; n points from the collider to the cloth's side, d is
// the cloth point's distance along it. The point gets the vertex-collider response (restitution, Coulomb
// friction, the push to the thickness), spread over its particles by w_k inv_m_k / sum w^2 inv_m so that the
// point itself changes by exactly that: Bridson et al. 2002 §7.1 with the collider's inverse mass zero.
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
      if (d >= thick) continue;
      const Vec3 dv =
          collider_velocity_change(out.v[i], Vec3::Zero(), n, cloth.restitution, combine_friction(cloth.friction, ci.friction));
      accumulate_contact(s, i, dv, eased_position_change(dv, n, d, thick, h));
    }
  });
}

// One vertex-triangle contact, normal n towards the vertex's side, end-of-step distance d: the collider response
// for a collider triangle; for a cloth one, the spring-capped cloth impulse in the proximity pass and, in the
// continuous pass (`crossed`), the inelastic stop with a position-only push back to the thickness.
void respond_vertex_triangle(const Model& m, const State& out, CollisionScratch& s, Index i, Index prim,
                             const PrimCorners& t, const Real* w, const Vec3& n, Real d, Real h, bool crossed) {
  const Real thick = m.particle_thickness[i];
  const Real mu = contact_friction(m, i, prim);
  if (!t.cloth) {
    Vec3 v_col = Vec3::Zero();
    for (int k = 0; k < 3; ++k) v_col += w[k] * (t.x1[k] - t.x0[k]) / h;
    const Vec3 dv = collider_velocity_change(out.v[i], v_col, n, m.cloths[m.collision.particle_cloth[i]].restitution, mu);
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

// Edge x[0]x[1] of a cloth against edge x[2]x[3] (another cloth edge, or a collider edge), moving linearly from x0 to
// x1 over the step (Bridson et al. 2002 §4): true when they meet within the thickness during the step and end closer
// than it along the direction back to the side they came from (crossing_normal, systems/collision/ccd.h); n and d are
// that direction and the end-of-step distance along it.
bool edge_edge_crossing(const Vec3 x0[4], const Vec3 x1[4], Real thick, EdgeProximity& px, Vec3& n, Real& d) {
  Real when;
  if (!edge_edge_ccd(x0, x1, thick, when, px)) return false;
  if (!crossing_normal(x0, x1, when, px, n)) return false;
  d = n.dot(((1 - px.s) * x1[0] + px.s * x1[1]) - ((1 - px.t) * x1[2] + px.t * x1[3]));
  return std::isfinite(d) && d < thick;
}

// Every cloth edge against the edges of the triangles its swept box meets: self-colliding cloths' edges
// against each other (each pair once, from the lower edge id), and every cloth edge against collider edges.
// on_edge(p, fixed, x0, x1, px, n, d, mu) for each pair that met within the thickness: p the four particles
// (collider vertices for p[2], p[3] when `fixed`), mu the mean friction of the two sides. A cloth edge that came
// from inside a collider is left to the proximity pass, which sends it out. Only pairs whose cloth particles
// pass keep(particles, count) are tested.
template <class Keep, class OnEdge>
void for_each_edge_crossing(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                            BroadMode mode, Keep&& keep, OnEdge&& on_edge) {
  const CollisionModel& c = m.collision;
  parallel_over(Index(c.edge_a.size()), contact_grain, [&](Index e) {
    const Index a = c.edge_a[e], b = c.edge_b[e];
    Aabb q = swept_box(in.x[a], out.x[a]);
    grow(q, in.x[b]);
    grow(q, out.x[b]);
    Aabb qi = q;
    qi.lo.array() -= c.max_thickness;
    qi.hi.array() += c.max_thickness;
    const Index cloth = c.particle_cloth[a];
    for_each_candidate(m, s, mode, q, [&](Index slot) {
      const Index prim = c.prim[slot];
      const bool fixed = prim >= m.tri_count;
      if (!fixed && !c.edge_contact[e]) return;
      for (int k = 0; k < 3; ++k) {
        Index p[4] = {a, b, 0, 0};
        Vec3 x0[4] = {in.x[a], in.x[b]}, x1[4] = {out.x[a], out.x[b]};
        Real mu;
        if (fixed) {
          const Index tri = prim - m.tri_count, g = c.mesh_tri_edge[3 * tri + k];
          if (c.mesh_edge_first_tri[g] != tri) continue;
          p[2] = c.mesh_edge_a[g];
          p[3] = c.mesh_edge_b[g];
          x0[2] = s.collider_x0[p[2]], x0[3] = s.collider_x0[p[3]];
          x1[2] = s.collider_x1[p[2]], x1[3] = s.collider_x1[p[3]];
          mu = collider_friction(m, a, c.mesh_tri_collider[tri]);
        } else {
          const Index f = c.tri_edge[3 * prim + k];
          if (f <= e || c.edge_first_tri[f] != prim) continue;
          p[2] = c.edge_a[f];
          p[3] = c.edge_b[f];
          if (c.edges_adjacent(a, b, p[2], p[3])) continue;
          if (!c.cloths_collide(cloth, c.particle_cloth[p[2]])) continue;
          x0[2] = in.x[p[2]], x0[3] = in.x[p[3]];
          x1[2] = out.x[p[2]], x1[3] = out.x[p[3]];
          mu = cloth_pair_friction(m, a, p[2]);
        }
        Aabb other = swept_box(x0[2], x1[2]);
        grow(other, x0[3]);
        grow(other, x1[3]);
        if (!boxes_overlap(qi, other) || !keep(p, fixed ? 2 : 4)) continue;
        EdgeProximity px;
        Vec3 n;
        Real d;
        if (!edge_edge_crossing(x0, x1, edge_pair_reach(m, p, fixed), px, n, d)) continue;
        if (d >= edge_pair_thickness(m, p, fixed, px.s, px.t)) continue;
        if (fixed) {
          const Vec3 nv = collider_edge_normal(c, s, c.mesh_tri_edge[3 * (prim - m.tri_count) + k]);
          if (n.dot(nv) < -0.2 * nv.norm()) continue;
        }
        on_edge(p, fixed, x0, x1, px, n, d, mu);
      }
    });
  });
}

// Every pair that meets along the step's linear trajectories (Bridson et al. 2002 §6.2: coplanar at some time
// with the vertex within the thickness of the triangle, or the edges within the thickness of each other) and
// ends closer than the thickness on the side it came from. Each cloth vertex against the triangles its swept box
// meets (on_vertex(i, prim, corners, w, n, d); for collider meshes only hits from the outside count: they are
// one-sided), each collider vertex against the cloth triangles (on_collider_vertex(t, v, w, n, d), n pointing
// from the vertex to the side the triangle must keep; a hit from the collider's outside, by the vertex's outward
// direction as in the proximity pass), then the edge pairs (for_each_edge_crossing). The continuous pass
// responds to them; the impact zones merge them. Only pairs whose cloth particles pass keep(particles, count)
// are tested (the zones' later passes skip pairs none of whose particles they moved).
template <class Keep, class OnVertex, class OnColliderVertex, class OnEdge>
void for_each_crossing(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                       BroadMode mode, Keep&& keep, OnVertex&& on_vertex, OnColliderVertex&& on_collider_vertex,
                       OnEdge&& on_edge) {
  const CollisionModel& c = m.collision;
  parallel_over(m.particle_count, contact_grain, [&](Index i) {
    const Real thick = m.particle_thickness[i];
    const Aabb q = swept_box(in.x[i], out.x[i]);
    for_each_candidate(m, s, mode, q, [&](Index slot) {
      const Index prim = c.prim[slot];
      const PrimCorners t = corners(m, in, out, s, prim);
      if (t.cloth && !c.vertex_meets_cloth_triangle(i, t.p)) return;
      if (!t.cloth && m.particle_inv_mass[i] == 0) return;
      const Index cloth_nodes[4] = {i, t.p[0], t.p[1], t.p[2]};
      if (!keep(cloth_nodes, t.cloth ? 4 : 1)) return;
      const Vec3 x0[4] = {in.x[i], t.x0[0], t.x0[1], t.x0[2]}, x1[4] = {out.x[i], t.x1[0], t.x1[1], t.x1[2]};
      Real when;
      TriangleProximity px;
      if (!vertex_triangle_ccd(x0, x1, thick, when, px)) return;
      const Real start = (x0[2] - x0[1]).cross(x0[3] - x0[1]).dot(x0[0] - x0[1]);
      if (!t.cloth && !(start > 0)) return;
      const Vec3 n = (start < 0 ? -1.0 : 1.0) * (x1[2] - x1[1]).cross(x1[3] - x1[1]).normalized();
      const Real d = n.dot(x1[0] - x1[1]);
      if (!std::isfinite(d) || d >= thick) return;
      on_vertex(i, prim, t, px.w, n, d);
    });
  });
  for_each_collider_vertex_pair(m, in, out, s, mode, [&](Index t, Index v) {
    const Index* p = &m.tri_index[3 * t];
    if (!keep(p, 3)) return;
    const Real thick = triangle_thickness(m, p);
    const Vec3 x0[4] = {s.collider_x0[v], in.x[p[0]], in.x[p[1]], in.x[p[2]]};
    const Vec3 x1[4] = {s.collider_x1[v], out.x[p[0]], out.x[p[1]], out.x[p[2]]};
    Real when;
    TriangleProximity px;
    if (!vertex_triangle_ccd(x0, x1, thick, when, px)) return;
    const Vec3 n0 = (x0[2] - x0[1]).cross(x0[3] - x0[1]);
    const Real way = n0.dot(x0[0] - x0[1]) > 0 ? -1 : 1;  // the triangle lay this way from the vertex along n0
    const Vec3 nv = collider_vertex_normal(c, s, v);
    if (way * n0.dot(nv) < -0.2 * n0.norm() * nv.norm()) return;
    const Vec3 n = way * (x1[2] - x1[1]).cross(x1[3] - x1[1]).normalized();
    const Real d = n.dot(x1[1] - x1[0]);
    if (!std::isfinite(d) || d >= thick) return;
    on_collider_vertex(t, v, px.w, n, d);
  });
  for_each_edge_crossing(m, in, out, s, mode, keep, on_edge);
}

// The continuous pass, last (Bridson et al. 2002 §6.2): every crossing of for_each_crossing is sent back to the
// side it came from, with the end-of-step distance along that direction restored to the thickness by an
// inelastic impulse and a position-only push spread over the cloth particles by their weights. Returns the
// contacts it responded to.
std::int64_t collide_continuous(const Model& m, const State& in, State& out, CollisionScratch& s, BroadMode mode,
                                Real h) {
  const CollisionModel& c = m.collision;
  clear_accumulators(m, s);
  for_each_crossing(
      m, in, out, s, mode, [](const Index*, int) { return true; },
      [&](Index i, Index prim, const PrimCorners& t, const Real* w, const Vec3& n, Real d) {
        respond_vertex_triangle(m, out, s, i, prim, t, w, n, d, h, true);
      },
      [&](Index t, Index v, const Real* w, const Vec3& n, Real d) {
        const Index* p = &m.tri_index[3 * t];
        const Real mu = collider_friction(m, p[0], c.mesh_tri_collider[c.mesh_vertex_first_tri[v]]);
        const Vec3 v_col = (s.collider_x1[v] - s.collider_x0[v]) / h;
        Vec3 dv[3], dx[3];
        if (!inelastic_separation(p, w, 3, m, out.v, v_col, n, d, triangle_thickness(m, p), mu, h, dv, dx)) return;
        for (int k = 0; k < 3; ++k) accumulate_contact(s, p[k], dv[k], dx[k]);
      },
      [&](const Index* p, bool fixed, const Vec3* x0, const Vec3* x1, const EdgeProximity& px, const Vec3& n, Real d,
          Real mu) {
        const Real wt[4] = {1 - px.s, px.s, -(1 - px.t), -px.t};
        const int count = fixed ? 2 : 4;
        Vec3 v_fixed = Vec3::Zero();
        if (fixed) v_fixed = ((1 - px.t) * (x1[2] - x0[2]) + px.t * (x1[3] - x0[3])) / h;
        Vec3 dv[4], dx[4];
        const Real thick = edge_pair_thickness(m, p, fixed, px.s, px.t);
        if (!inelastic_separation(p, wt, count, m, out.v, v_fixed, n, d, thick, mu, h, dv, dx)) return;
        for (int k = 0; k < count; ++k) accumulate_contact(s, p[k], dv[k], dx[k]);
      });
  return apply_accumulated(m, out, s);
}

// Rigid impact zones (systems/collision/impact_zones.h), after continuous passes that left crossings: each pass finds
// the pairs the continuous pass would still respond to (for_each_crossing), merges their nodes (cloth particles;
// collider vertices as node particle_count + v) into zones, and moves the zones that grew, until a pass finds none.
// It stops early, the step counted as unresolved, when a pass merges nothing (every pair found lies within one zone)
// or after model.collision.zone_iterations passes. The pairs are those of the continuous pass, met within the
// thickness, not only actual crossings: a squeezed sheet left micrometres from a body would otherwise be held there
// by its zone, crossing and all (docs/performance.md, "Rigid impact zones"). So an unresolved step may end with pairs
// that only graze within the thickness.
void resolve_impact_zones(const Model& m, const State& in, State& out, CollisionScratch& s, BroadMode mode, Real h) {
  const CollisionModel& c = m.collision;
  ZoneScratch& z = s.zones;
  const Index pc = m.particle_count;
  reset_zones(z);
  ++z.figures.steps;
  bool clean = false;
  for (int pass = 0; pass < c.zone_iterations; ++pass) {
    build_broad_phase(m, in, out, s);
    std::atomic<std::int64_t> pairs{0}, links{0};
    auto add = [&](const Index* nodes, int count) {
      pairs.fetch_add(1, std::memory_order_relaxed);
      if (const int merged = add_zone_pair(z, nodes, count)) links.fetch_add(merged, std::memory_order_relaxed);
    };
    // After the first pass, a pair none of whose cloth particles is in a zone has not moved since that pass
    // found it apart (collider vertices move the same in every pass): only pairs touching a zone are tested. A
    // particle this pass adds to a zone has not moved yet, so whether a thread sees its flag does not matter.
    auto moved = [&](const Index* p, int count) {
      if (pass == 0) return true;
      for (int k = 0; k < count; ++k)
        if (std::atomic_ref<std::uint8_t>(z.flag[p[k]]).load(std::memory_order_relaxed) & zone_member) return true;
      return false;
    };
    for_each_crossing(
        m, in, out, s, mode, moved,
        [&](Index i, Index, const PrimCorners& t, const Real*, const Vec3&, Real) {
          const Index base = t.cloth ? 0 : pc;
          const Index nodes[4] = {i, base + t.p[0], base + t.p[1], base + t.p[2]};
          add(nodes, 4);
        },
        [&](Index t, Index v, const Real*, const Vec3&, Real) {
          const Index* p = &m.tri_index[3 * t];
          const Index nodes[4] = {pc + v, p[0], p[1], p[2]};
          add(nodes, 4);
        },
        [&](const Index* p, bool fixed, const Vec3*, const Vec3*, const EdgeProximity&, const Vec3&, Real, Real) {
          const Index base = fixed ? pc : 0;
          const Index nodes[4] = {p[0], p[1], base + p[2], base + p[3]};
          add(nodes, 4);
        });
    ++z.figures.passes;
    if (pairs.load() == 0) {
      clean = true;
      break;
    }
    if (links.load() == 0) break;
    gather_zones(z);
    rigidify_zones(m, in, out, s, h);
  }
  if (!clean) ++z.figures.unresolved;
  count_zones(z);
}

}  // namespace

void place_colliders(const Model& m, Real time, Real h, CollisionScratch& s) {
  const CollisionModel& c = m.collision;
  if (!c.animated) return;
  // The step's own start time: with timestep="auto" the steps of a frame differ in length, so a step count
  // times h would place the body at the wrong time.
  auto at = [&](const ColliderInfo& ci, Real t, std::vector<Vec3>& dst) {
    const FrameBlend b = frame_blend(ci, m.start_frame, m.fps, t);
    parallel_over(ci.vertex_end - ci.vertex_begin, particle_grain,
                  [&](Index k) { dst[ci.vertex_begin + k] = collider_vertex(c, ci, b, ci.vertex_begin + k); });
  };
  for (const ColliderInfo& ci : c.colliders) {
    if (ci.shape != ColliderShape::sequence) continue;
    at(ci, time, s.collider_x0);
    at(ci, time + h, s.collider_x1);
  }
}

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

void collide(const Model& m, const State& in, State& out, Workspace& ws, Real h) {
  const CollisionModel& c = m.collision;
  if (!c.enabled) return;
  const auto t0 = std::chrono::steady_clock::now();
  CollisionScratch& s = ws.collision;
  place_colliders(m, in.time, h, s);
  push_out_deep_vertices(m, in, out, s, h);
  const bool broad = !c.prim.empty();
  if (broad) build_broad_phase(m, in, out, s);
  const BroadMode mode = c.broad_phase == BroadPhase::bvh ? BroadMode::bvh : BroadMode::hash;

  for (int iter = 0; iter < c.iterations; ++iter) {
    clear_accumulators(m, s);
    collide_analytic(m, out, s, h);
    if (broad) {
      for_each_proximity(
          m, in, out, s, mode,
          [&](Index i, Index prim, const PrimCorners& t, const TriangleProximity& px, Real d) {
            if (!t.cloth && m.particle_inv_mass[i] == 0) return;
            respond_vertex_triangle(m, out, s, i, prim, t, px.w, px.n, d, h, false);
          },
          [&](Index e, Index f, const EdgeProximity& px, Real d) {
            const Index p[4] = {c.edge_a[e], c.edge_b[e], c.edge_a[f], c.edge_b[f]};
            const Real wt[4] = {1 - px.s, px.s, -(1 - px.t), -px.t};
            const Real mu = cloth_pair_friction(m, p[0], p[2]);
            Vec3 dv[4];
            const Real thick = edge_pair_thickness(m, p, false, px.s, px.t);
            if (!cloth_impulse(p, wt, 4, m, out.v, px.n, d, thick, mu, h, dv)) return;
            for (int k = 0; k < 4; ++k) accumulate_contact(s, p[k], dv[k], h * dv[k]);
          },
          [&](Index t, Index v, const TriangleProximity& px, const Vec3& n, Real d) {
            const Index* p = &m.tri_index[3 * t];
            const Real mu = collider_friction(m, p[0], c.mesh_tri_collider[c.mesh_vertex_first_tri[v]]);
            respond_collider_point(m, out, s, p, px.w, 3, s.collider_x0[v], s.collider_x1[v], n, d,
                                   triangle_thickness(m, p), mu, h);
          },
          [&](Index e, Index g, const EdgeProximity& px, Real d) {
            const Index p[2] = {c.edge_a[e], c.edge_b[e]};
            const Real w[2] = {1 - px.s, px.s};
            const Index ga = c.mesh_edge_a[g], gb = c.mesh_edge_b[g];
            const Vec3 c0 = (1 - px.t) * s.collider_x0[ga] + px.t * s.collider_x0[gb];
            const Vec3 c1 = (1 - px.t) * s.collider_x1[ga] + px.t * s.collider_x1[gb];
            const Real mu = collider_friction(m, p[0], c.mesh_tri_collider[c.mesh_edge_first_tri[g]]);
            const Real thick = edge_thickness_at(m, p[0], p[1], px.s);
            respond_collider_point(m, out, s, p, w, 2, c0, c1, px.n, d, thick, mu, h);
          });
    }
    const std::int64_t found = apply_accumulated(m, out, s);
    if (iter == 0) s.contacts_found += found;
    if (found == 0) break;
  }
  // The continuous pass repeats too (its responses are averaged per vertex, so one pass may leave part of a
  // crossing), on boxes rebuilt around the corrected positions, until a pass finds nothing. When the last pass
  // still found crossings, the impact zones take over: a step that ends clean costs nothing more.
  bool crossings_left = false;
  for (int pass = 0; broad && pass < c.iterations; ++pass) {
    if (pass > 0) build_broad_phase(m, in, out, s);
    crossings_left = collide_continuous(m, in, out, s, mode, h) > 0;
    if (!crossings_left) break;
  }
  if (crossings_left && c.impact_zones()) resolve_impact_zones(m, in, out, s, mode, h);
  ws.seconds_collide += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<std::array<Index, 3>> list_proximities(const Model& m, const State& in, const State& out,
                                                   CollisionScratch& s, BroadMode mode) {
  std::vector<std::array<Index, 3>> found;
  std::mutex lock;
  auto add = [&](Index kind, Index a, Index b) {
    std::lock_guard g(lock);
    found.push_back({kind, a, b});
  };
  for_each_proximity(
      m, in, out, s, mode,
      [&](Index i, Index prim, const PrimCorners&, const TriangleProximity&, Real) { add(0, i, prim); },
      [&](Index e, Index f, const EdgeProximity&, Real) { add(1, e, f); },
      [&](Index t, Index v, const TriangleProximity&, const Vec3&, Real) { add(2, t, v); },
      [&](Index e, Index g, const EdgeProximity&, Real) { add(3, e, g); });
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace clothsim
