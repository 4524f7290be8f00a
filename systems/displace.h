#pragma once
// The position corrections after the integrator (strain limit, stitch pass, cloth-cloth holds) move a particle and
// its velocity together, so that x' = x + h v' stays true for the step just taken.
#include "core/model.h"

namespace clothsim {

// Moves particle i by dx and its velocity by dx / h.
inline void displace(State& out, Index i, const Vec3& dx, Real h) {
  out.x[i] += dx;
  out.v[i] += dx / h;
}

}  // namespace clothsim
