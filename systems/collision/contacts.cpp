#include "systems/collision/contacts.h"

#include "systems/collision/response.h"
#include "systems/parallel.h"

namespace clothsim {

Index find_proximities(const Model& m, const State& in, const State& out, CollisionScratch& s, BroadMode mode) {
  return fill_contacts(s, [&](auto&& add) {
    for_each_proximity(
        m, in, out, s, mode,
        [&](Index i, Index prim, const PrimCorners&, const TriangleProximity& px, Real d) {
          add(Contact{ContactKind::vertex_triangle, i, prim, {px.w[0], px.w[1], px.w[2]}, px.n, d});
        },
        [&](Index e, Index f, const EdgeProximity& px, Real d) {
          add(Contact{ContactKind::cloth_edges, e, f, {px.s, px.t, 0}, px.n, d});
        },
        [&](Index t, Index v, const TriangleProximity& px, const Vec3& n, Real d) {
          add(Contact{ContactKind::collider_vertex, t, v, {px.w[0], px.w[1], px.w[2]}, n, d});
        },
        [&](Index e, Index g, const EdgeProximity& px, Real d) {
          add(Contact{ContactKind::collider_edge, e, g, {px.s, px.t, 0}, px.n, d});
        });
  });
}

namespace {
// An edge pair's ends: cloth edge e's, then edge f's (a collider edge's vertices when fixed).
void edge_pair_ends(const CollisionModel& c, Index e, Index f, bool fixed, Index p[4]) {
  p[0] = c.edge_a[e];
  p[1] = c.edge_b[e];
  p[2] = fixed ? c.mesh_edge_a[f] : c.edge_a[f];
  p[3] = fixed ? c.mesh_edge_b[f] : c.edge_b[f];
}
}  // namespace

void mark_crossed(const Model& m, CollisionScratch& s, Index found) {
  std::fill(s.crossed.begin(), s.crossed.end(), std::uint8_t(0));
  for (Index k = 0; k < found; ++k) {
    Index nodes[4] = {m.particle_count, m.particle_count, m.particle_count, m.particle_count};
    contact_nodes(m, s.contacts[std::size_t(k)], nodes);
    for (const Index x : nodes)
      if (x < m.particle_count) s.crossed[x] = 1;
  }
}

void contact_nodes(const Model& m, const Contact& k, Index nodes[4]) {
  const CollisionModel& c = m.collision;
  const Index pc = m.particle_count;
  switch (k.kind) {
    case ContactKind::vertex_triangle: {
      const bool cloth = k.b < m.tri_count;
      const Index* p = cloth ? &m.tri_index[3 * k.b] : &c.mesh_tri_index[3 * (k.b - m.tri_count)];
      const Index base = cloth ? 0 : pc;
      nodes[0] = k.a;
      for (int j = 0; j < 3; ++j) nodes[j + 1] = base + p[j];
      return;
    }
    case ContactKind::collider_vertex: {
      const Index* p = &m.tri_index[3 * k.a];
      nodes[0] = pc + k.b;
      for (int j = 0; j < 3; ++j) nodes[j + 1] = p[j];
      return;
    }
    case ContactKind::cloth_edges:
    case ContactKind::collider_edge: {
      const bool fixed = k.kind == ContactKind::collider_edge;
      edge_pair_ends(c, k.a, k.b, fixed, nodes);
      if (fixed) {
        nodes[2] += pc;
        nodes[3] += pc;
      }
      return;
    }
  }
}

namespace {

// An edge pair of the continuous pass: its particles (collider vertices for p[2], p[3] when fixed) at the start
// and end of the step, and the friction of its two sides, as for_each_edge_crossing found it.
void respond_edge_pair_crossing(const Model& m, const State& in, const State& out, CollisionScratch& s,
                                const Contact& k, Real h) {
  const CollisionModel& c = m.collision;
  const bool fixed = k.kind == ContactKind::collider_edge;
  Index p[4];
  edge_pair_ends(c, k.a, k.b, fixed, p);
  const Index a = p[0], b = p[1];
  const std::vector<Vec3>& far0 = fixed ? s.collider_x0 : in.x;
  const std::vector<Vec3>& far1 = fixed ? s.collider_x1 : out.x;
  const Vec3 x0[4] = {in.x[a], in.x[b], far0[p[2]], far0[p[3]]};
  const Vec3 x1[4] = {out.x[a], out.x[b], far1[p[2]], far1[p[3]]};
  const Real mu = fixed ? collider_friction(m, a, c.mesh_tri_collider[c.mesh_edge_first_tri[k.b]])
                        : cloth_pair_friction(m, a, p[2]);
  EdgeProximity px;
  px.s = k.w[0];
  px.t = k.w[1];
  respond_edge_crossing(m, out, s, p, fixed, x0, x1, px, k.n, k.d, mu, h);
}

void respond_contact(const Model& m, const State& in, const State& out, CollisionScratch& s, const Contact& k,
                     Real h, bool crossed) {
  switch (k.kind) {
    case ContactKind::vertex_triangle:
      if (k.b >= m.tri_count && m.particle_inv_mass[k.a] == 0) return;  // a pinned vertex is not pushed off a body
      respond_vertex_triangle(m, out, s, k.a, k.b, corners(m, in, out, s, k.b), k.w, k.n, k.d, h, crossed);
      return;
    case ContactKind::collider_vertex:
      if (crossed) {
        respond_collider_vertex_crossing(m, out, s, k.a, k.b, k.w, k.n, k.d, h);
      } else {
        TriangleProximity px;
        for (int j = 0; j < 3; ++j) px.w[j] = k.w[j];
        respond_collider_vertex(m, out, s, k.a, k.b, px, k.n, k.d, h);
      }
      return;
    case ContactKind::cloth_edges:
    case ContactKind::collider_edge:
      if (crossed) {
        respond_edge_pair_crossing(m, in, out, s, k, h);
      } else {
        EdgeProximity px;
        px.s = k.w[0];
        px.t = k.w[1];
        px.n = k.n;
        if (k.kind == ContactKind::cloth_edges) respond_cloth_edges(m, out, s, k.a, k.b, px, k.d, h);
        else respond_collider_edge(m, out, s, k.a, k.b, px, k.d, h);
      }
      return;
  }
}

}  // namespace

void respond_contacts(const Model& m, const State& in, const State& out, CollisionScratch& s, Real h,
                      bool crossed) {
  parallel_over(s.contact_count, contact_grain,
                [&](Index k) { respond_contact(m, in, out, s, s.contacts[std::size_t(k)], h, crossed); });
}

}  // namespace clothsim
