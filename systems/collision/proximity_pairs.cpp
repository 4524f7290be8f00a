#include "systems/collision/proximity_pairs.h"

#include "systems/collision/contacts.h"

namespace clothsim {

void respond_proximities(const Model& m, const State& in, const State& out, CollisionScratch& s, BroadMode mode,
                         Real h) {
  find_proximities(m, in, out, s, mode);
  respond_contacts(m, in, out, s, h, false);
}

}  // namespace clothsim
