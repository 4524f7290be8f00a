#pragma once
// Random accelerations reproducible from the scene's seed, as gusts: a value-noise field in space and time
// (Perlin 1985's lattice noise without gradients). Each axis draws a value uniform over [lo, hi] at the nodes of
// a lattice of spacing cellSize (m) in space and period (s) in time, and a particle feels the field at its
// position and the step's time, interpolated trilinearly in space and by a smoothstep in time. The field does not
// depend on the time step (a fresh draw per step would be a random walk whose energy grows with 1/h), neighbours
// move together (no jitter of the stiffest modes), and every value stays within [lo, hi]. The node values come
// from a counter-based generator (a hash of seed, node and axis), so they do not depend on which thread computes
// them nor on what came before, and a resumed run draws exactly what an uninterrupted one did.
#include <cmath>
#include <cstdint>

#include "core/math.h"
#include "core/scene_desc.h"

namespace clothsim {

inline std::uint64_t mix64(std::uint64_t z) {  // splitmix64 finaliser
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

inline double unit_from_bits(std::uint64_t h) { return double(h >> 11) * 0x1.0p-53; }  // [0, 1), 53 bits

// Uniform in [0, 1) from (seed, step, particle, axis): a reproducible start vector (systems/stability.cpp).
inline double random_unit(std::uint64_t seed, std::int64_t step, std::int64_t particle, int axis) {
  return unit_from_bits(mix64(mix64(mix64(seed) ^ std::uint64_t(step)) ^ (std::uint64_t(particle) * 3 + axis)));
}

// Acceleration at position x and time t (s since the start frame): the gust field above, per axis over [lo, hi],
// lo = -amplitude when the negative sign is allowed (else 0), hi = +amplitude when the positive sign is allowed
// (else 0). One hash per lattice node (of seed and time, then of the node's cell) gives all three axes, 21 bits
// each: 18 hashes for the 16 nodes around a point, so the field costs little more than a draw per axis.
inline Vec3 random_acceleration(const RandomForceDesc& r, Real t, const Vec3& x) {
  const Real ts = t / r.period;
  const Real tf = std::floor(ts);
  const std::int64_t n = std::int64_t(tf);
  Real wt = ts - tf;
  wt = wt * wt * (3 - 2 * wt);  // smoothstep: the gust's rate of change is continuous at the time nodes
  std::int64_t c[3];
  Real w[3];
  for (int k = 0; k < 3; ++k) {
    const Real u = x[k] / r.cell_size, f = std::floor(u);
    const bool ok = std::abs(f) < 1e15;  // a blown-up particle (the run is about to stop) reads node 0
    c[k] = ok ? std::int64_t(f) : 0;
    w[k] = ok ? u - f : 0;
  }
  Vec3 value = Vec3::Zero();
  const std::uint64_t hs = mix64(r.seed);
  for (int a = 0; a < 2; ++a) {
    const std::uint64_t ha = mix64(hs ^ std::uint64_t(n + a));
    for (int corner = 0; corner < 8; ++corner) {
      const int i = corner & 1, j = (corner >> 1) & 1, k = corner >> 2;
      const std::uint64_t cell = std::uint64_t(c[0] + i) * 0x9e3779b97f4a7c15ULL ^
                                 std::uint64_t(c[1] + j) * 0xc2b2ae3d27d4eb4fULL ^
                                 std::uint64_t(c[2] + k) * 0x165667b19e3779f9ULL;
      const std::uint64_t h = mix64(ha ^ cell);
      const Real weight =
          (a ? wt : 1 - wt) * (i ? w[0] : 1 - w[0]) * (j ? w[1] : 1 - w[1]) * (k ? w[2] : 1 - w[2]);
      for (int axis = 0; axis < 3; ++axis)
        value[axis] += weight * (Real((h >> (21 * axis)) & 0x1fffff) * 0x1.0p-21);  // [0, 1) in 2^-21 steps
    }
  }
  Vec3 result;
  for (int axis = 0; axis < 3; ++axis) {
    const Real lo = r.allow[2 * axis] ? -r.amplitude : 0, hi = r.allow[2 * axis + 1] ? r.amplitude : 0;
    result[axis] = lo + (hi - lo) * value[axis];
  }
  return result;
}

}  // namespace clothsim
