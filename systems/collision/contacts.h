#pragma once
// The contact buffer between detection and response (DESIGN.md, "systems/collision/"): a pass's detection fills
// s.contacts with every pair it finds, and the response consumes them. Detection and response both read the
// positions and velocities the pass started from (responses only add to the per-particle accumulators), so
// splitting them changes nothing; the buffer's order is the threads' and does not matter, because the
// accumulators' fixed-point sums are the same in any order (systems/collision/response.h).
#include <atomic>

#include "systems/collision/continuous_pairs.h"
#include "systems/collision/proximity_pairs.h"

namespace clothsim {

// Runs find(add) and keeps every contact it adds in s.contacts[0, s.contact_count). The buffer has a capacity
// and a counter: a pass that finds more than the capacity grows it (the only allocation, once per new
// high-water mark) and runs find again, which finds the same pairs.
template <class Find>
Index fill_contacts(CollisionScratch& s, Find&& find) {
  for (;;) {
    s.contact_count = 0;
    const Index capacity = Index(s.contacts.size());
    find([&](const Contact& k) {
      const Index slot = std::atomic_ref<Index>(s.contact_count).fetch_add(1, std::memory_order_relaxed);
      if (slot < capacity) s.contacts[std::size_t(slot)] = k;
    });
    if (s.contact_count <= capacity) return s.contact_count;
    s.contacts.resize(2 * std::size_t(s.contact_count));
  }
}

// The proximity pass's pairs (for_each_proximity) into s.contacts; returns their count.
Index find_proximities(const Model& model, const State& in, const State& out, CollisionScratch& s, BroadMode mode);

// The continuous pass's pairs (for_each_crossing) into s.contacts, testing only pairs whose cloth particles pass
// keep(particles, count), from cloth elements whose swept box passes near(box); returns their count.
template <class Keep, class Near = Everywhere>
Index find_crossings(const Model& m, const State& in, const State& out, CollisionScratch& s, BroadMode mode,
                     Keep&& keep, Near&& near = Near{}) {
  return fill_contacts(s, [&](auto&& add) {
    for_each_crossing(
        m, in, out, s, mode, keep, near,
        [&](Index i, Index prim, const PrimCorners&, const Real* w, const Vec3& n, Real d) {
          add(Contact{ContactKind::vertex_triangle, i, prim, {w[0], w[1], w[2]}, n, d});
        },
        [&](Index t, Index v, const Real* w, const Vec3& n, Real d) {
          add(Contact{ContactKind::collider_vertex, t, v, {w[0], w[1], w[2]}, n, d});
        },
        [&](Index e, Index f, bool fixed, const EdgeProximity& px, const Vec3& n, Real d) {
          add(Contact{fixed ? ContactKind::collider_edge : ContactKind::cloth_edges, e, f, {px.s, px.t, 0}, n, d});
        });
  });
}

// Whether one of the cloth particles p[0, count) is in a pair the latest continuous pass found (s.crossed).
inline bool crossed(const CollisionScratch& s, const Index* p, int count) {
  for (int k = 0; k < count; ++k)
    if (s.crossed[p[k]]) return true;
  return false;
}
// s.crossed: 1 for the cloth particles of the `found` pairs in s.contacts, 0 for the rest.
void mark_crossed(const Model& model, CollisionScratch& s, Index found);

// The four nodes of contact k, for zone merging: cloth particles, and collider vertex v as node
// particle_count + v.
void contact_nodes(const Model& model, const Contact& k, Index nodes[4]);

// Every buffered contact's response added to the accumulators: the proximity pass's (crossed false: the
// spring-capped cloth impulse, the collider response) or the continuous pass's (crossed: the inelastic stop with
// a position-only push back to the thickness).
void respond_contacts(const Model& model, const State& in, const State& out, CollisionScratch& s, Real h,
                      bool crossed);

}  // namespace clothsim
