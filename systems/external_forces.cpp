#include "systems/external_forces.h"

#include "systems/parallel.h"

namespace clothsim {

void apply_external_forces(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Real time,
                           std::span<const Vec3> normal, std::span<Vec3> f) {
  parallel_over(m.particle_count, particle_grain,
                [&](Index i) { f[i] = external_acceleration(m, i, f[i], x[i], v[i], time, normal); });
}

}  // namespace clothsim
