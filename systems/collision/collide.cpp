#include "systems/collision/collide.h"

#include <algorithm>

#include "systems/contact_filter.h"
#include "systems/collision/contacts.h"
#include "systems/collision/continuous_pairs.h"
#include "systems/collision/impact_zones.h"
#include "systems/collision/proximity_pairs.h"
#include "systems/collision/push_out.h"
#include "systems/collision/response.h"

namespace clothsim {
namespace {

// One proximity pass's detection and responses into the accumulators (not applied): the analytic colliders, then
// every pair of the broad phase when there is one.
void respond_proximity_pass(const Model& m, const State& in, State& out, CollisionScratch& s, Real h) {
  clear_accumulators(m, s);
  collide_analytic(m, out, s, h);
  if (!m.collision.prim.empty()) respond_proximities(m, in, out, s, broad_mode(m.collision), h);
}

}  // namespace

CollideCounts collide(const Model& m, const State& in, State& out, Workspace& ws, Real h) {
  const CollisionModel& c = m.collision;
  CollideCounts counts;
  if (!c.enabled) return counts;
  CollisionScratch& s = ws.collision;
  place_colliders(m, in.time, h, s);
  push_out_deep_vertices(m, in, out, s, h);
  const bool broad = !c.prim.empty();
  if (broad) {
    build_broad_phase(m, in, out, s);
    make_candidate_lists(m, in, out, s);
  }
  const BroadMode mode = broad_mode(c);

  // The proximity passes (Bridson et al. 2002 §7): every contact of a pass is averaged per vertex, applied, and
  // the pass repeats on the corrected positions until it finds nothing.
  // The collider contacts they find are also the holds of the next implicit solve (systems/contact_filter.h).
  clear_contact_holds(m, s);
  for (int iter = 0; iter < c.iterations; ++iter) {
    respond_proximity_pass(m, in, out, s, h);
    const std::int64_t found = apply_accumulated(m, out, s);
    if (iter == 0) counts.contacts = found;
    if (found == 0) break;
  }
  // The continuous pass repeats too (its responses are averaged per vertex, so one pass may leave part of a
  // crossing), on boxes rebuilt around the corrected positions, until a pass finds nothing. When the last pass
  // still found crossings, the impact zones take over: a step that ends clean costs nothing more.
  bool crossings_left = false;
  for (int pass = 0; broad && pass < c.iterations; ++pass) {
    if (pass > 0) build_cloth_broad_phase(m, in, out, s);
    crossings_left = collide_continuous(m, in, out, s, mode, h, pass > 0) > 0;
    if (!crossings_left) break;
  }
  if (crossings_left && c.impact_zones()) counts.zones = resolve_impact_zones(m, in, out, s, mode, h);
  gather_contact_holds(m, s, out);
  return counts;
}

void prime_contact_holds(const Model& m, State& state, Workspace& ws, Real h) {
  CollisionScratch& s = ws.collision;
  if (s.acc_hold.empty()) return;  // sized only with collisions and the filter on
  place_colliders(m, state.time, h, s);
  if (!m.collision.prim.empty()) build_broad_phase(m, state, state, s);
  clear_contact_holds(m, s);
  respond_proximity_pass(m, state, state, s, h);
  gather_contact_holds(m, s, state);
}

std::vector<std::array<Index, 3>> list_proximities(const Model& m, const State& in, const State& out,
                                                   CollisionScratch& s, BroadMode mode) {
  find_proximities(m, in, out, s, mode);
  return list_contacts(s);
}

std::vector<std::array<Index, 3>> list_contacts(const CollisionScratch& s) {
  std::vector<std::array<Index, 3>> found;
  for (Index k = 0; k < s.contact_count; ++k) {
    const Contact& c = s.contacts[std::size_t(k)];
    found.push_back({Index(c.kind), c.a, c.b});
  }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace clothsim
