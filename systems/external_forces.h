#pragma once
#include <span>

#include "core/model.h"
#include "systems/random_force.h"

namespace clothsim {

// Turns particle i's accumulated spring force into its acceleration, adding gravity and the constant external
// acceleration, the seeded gust field at the particle and the step's time (systems/random_force.h), air damping -c v, and Provot's wind
// F = k_w A [n.(u_w - v)] n (A the particle's lumped area, n its unit normal). Pinned particles get zero.
// One expression for the separate pass below and the fused one of systems/forces.h, so both round alike.
inline Vec3 external_acceleration(const Model& m, Index i, const Vec3& spring_force, const Vec3& x, const Vec3& v,
                                  Real time, std::span<const Vec3> normal) {
  const Real inv_m = m.particle_inv_mass[i];
  Vec3 force = spring_force;
  if (m.wind_strength != 0) {
    const Vec3& n = normal[i];
    force += m.wind_strength * m.particle_area[i] * n.dot(m.wind_velocity - v) * n;
  }
  Vec3 accel = m.gravity - m.air_damping * v;
  if (m.random.amplitude != 0) accel += random_acceleration(m.random, time, x);
  const Real free = inv_m > 0 ? 1.0 : 0.0;
  return inv_m * force + free * accel;
}

// f[i] = external_acceleration(i, f[i], x[i], v[i]) for every particle.
void apply_external_forces(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v,
                           Real time, std::span<const Vec3> normal, std::span<Vec3> f);

}  // namespace clothsim
