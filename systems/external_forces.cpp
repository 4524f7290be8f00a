#include "systems/external_forces.h"

#include "systems/parallel.h"
#include "systems/random_force.h"

namespace clothsim {

void apply_external_forces(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, std::int64_t step,
                           std::span<const Vec3> normal, std::span<Vec3> f) {
  (void)x;
  const bool wind = m.wind_strength != 0;
  const bool random = m.random.amplitude != 0;
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    const Real inv_m = m.particle_inv_mass[i];
    Vec3 force = f[i];
    if (wind) {
      const Vec3& n = normal[i];
      force += m.wind_strength * m.particle_area[i] * n.dot(m.wind_velocity - v[i]) * n;
    }
    Vec3 accel = m.gravity - m.air_damping * v[i];
    if (random)
      for (int axis = 0; axis < 3; ++axis) accel[axis] += random_acceleration(m.random, step, i, axis);
    const Real free = inv_m > 0 ? 1.0 : 0.0;
    f[i] = inv_m * force + free * accel;
  });
}

}  // namespace clothsim
