#include "systems/collision/continuous_pairs.h"

#include "systems/collision/contacts.h"

namespace clothsim {

std::int64_t collide_continuous(const Model& m, const State& in, State& out, CollisionScratch& s, BroadMode mode,
                                Real h) {
  clear_accumulators(m, s);
  find_crossings(m, in, out, s, mode, [](const Index*, int) { return true; });
  respond_contacts(m, in, out, s, h, true);
  return apply_accumulated(m, out, s);
}

}  // namespace clothsim
