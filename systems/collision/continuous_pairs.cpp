#include "systems/collision/continuous_pairs.h"

#include "systems/collision/contacts.h"
#include "systems/collision/reach_grid.h"

namespace clothsim {

std::int64_t collide_continuous(const Model& m, const State& in, State& out, CollisionScratch& s, BroadMode mode,
                                Real h, bool retest) {
  clear_accumulators(m, s);
  if (retest) build_reach_grid(in, out, s.crossed, reach_of_a_particle(m, s), s.crossed_reach);
  const Index found = find_crossings(
      m, in, out, s, mode, [&](const Index* p, int count) { return !retest || crossed(s, p, count); },
      [&](const Aabb& q) { return !retest || reaches(s.crossed_reach, q); });
  mark_crossed(m, s, found);
  respond_contacts(m, in, out, s, h, true);
  return apply_accumulated(m, out, s);
}

}  // namespace clothsim
