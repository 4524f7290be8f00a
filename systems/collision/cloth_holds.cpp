#include "systems/collision/cloth_holds.h"

#include <algorithm>

#include "systems/collision/broad_phase.h"
#include "systems/collision/contacts.h"
#include "systems/displace.h"

namespace clothsim {
namespace {

// Shorter than the held distance by less than this is round-off of an earlier projection, not a move (m).
constexpr Real hold_slack = 1e-9;

// The pair's four particles (contact_nodes: all cloth particles for a cloth-cloth pair) and the coefficients of
// its gap n . sum c_k x_k.
void hold_terms(const Model& m, const Contact& k, Index p[4], Real c[4]) {
  contact_nodes(m, k, p);
  if (k.kind == ContactKind::vertex_triangle) {
    c[0] = 1;
    for (int j = 0; j < 3; ++j) c[j + 1] = -k.w[j];
    return;
  }
  c[0] = 1 - k.w[0];
  c[1] = k.w[0];
  c[2] = -(1 - k.w[1]);
  c[3] = -k.w[1];
}

}  // namespace

void gather_cloth_holds(const Model& m, const State& in, const State& out, CollisionScratch& s) {
  s.cloth_holds.clear();
  const CollisionModel& c = m.collision;
  if (!c.cloth_contact || c.prim.empty()) return;
  build_cloth_broad_phase(m, in, out, s);
  const Index found = find_proximities(m, in, out, s, cloth_side(broad_mode(c)));
  for (Index k = 0; k < found; ++k) {
    const Contact& ct = s.contacts[std::size_t(k)];
    const bool cloth = ct.kind == ContactKind::cloth_edges ||
                       (ct.kind == ContactKind::vertex_triangle && ct.b < m.tri_count);
    if (!cloth || !(ct.d > 0)) continue;
    s.cloth_holds.push_back(ct);
  }
  std::sort(s.cloth_holds.begin(), s.cloth_holds.end(), [](const Contact& x, const Contact& y) {
    if (x.kind != y.kind) return x.kind < y.kind;
    if (x.a != y.a) return x.a < y.a;
    return x.b < y.b;
  });
}

Index apply_cloth_holds(const Model& m, State& out, const CollisionScratch& s, Real h,
                        const std::function<void(Index)>& on_move) {
  Index moved = 0;
  for (const Contact& k : s.cloth_holds) {
    Index p[4];
    Real c[4];
    hold_terms(m, k, p, c);
    Real gap = 0, weight = 0;
    for (int j = 0; j < 4; ++j) {
      gap += c[j] * k.n.dot(out.x[p[j]]);
      weight += c[j] * c[j] * m.particle_inv_mass[p[j]];
    }
    const Real short_by = k.d - gap;
    if (!(short_by > hold_slack) || !(weight > 0)) continue;
    const Real lambda = short_by / weight;
    for (int j = 0; j < 4; ++j) {
      displace(out, p[j], (lambda * c[j] * m.particle_inv_mass[p[j]]) * k.n, h);
      if (on_move) on_move(p[j]);
    }
    ++moved;
  }
  return moved;
}

}  // namespace clothsim
