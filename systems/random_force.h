#pragma once
// Random accelerations reproducible from the scene's seed: a counter-based generator (a hash of seed, step,
// particle and axis), so the value does not depend on which thread computes it nor on what came before,
// and a resumed run draws exactly what an uninterrupted one did.
#include <cstdint>

#include "core/scene_desc.h"

namespace clothsim {

inline std::uint64_t mix64(std::uint64_t z) {  // splitmix64 finaliser
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Uniform in [0, 1) with 53 random bits.
inline double random_unit(std::uint64_t seed, std::int64_t step, std::int64_t particle, int axis) {
  const std::uint64_t h = mix64(mix64(mix64(seed) ^ std::uint64_t(step)) ^ (std::uint64_t(particle) * 3 + axis));
  return double(h >> 11) * 0x1.0p-53;
}

// Acceleration on one axis: uniform over [lo, hi], lo = -amplitude when the negative sign is allowed (else 0),
// hi = +amplitude when the positive sign is allowed (else 0).
inline Real random_acceleration(const RandomForceDesc& r, std::int64_t step, std::int64_t particle, int axis) {
  const Real lo = r.allow[2 * axis] ? -r.amplitude : 0;
  const Real hi = r.allow[2 * axis + 1] ? r.amplitude : 0;
  return lo + (hi - lo) * random_unit(r.seed, step, particle, axis);
}

}  // namespace clothsim
