#include "systems/normals.h"

#include "systems/parallel.h"

namespace clothsim {

void eval_normals(const Model& m, std::span<const Vec3> x, std::span<Vec3> normal) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    Vec3 sum = Vec3::Zero();
    for (Index k = m.particle_tri_offset[i]; k < m.particle_tri_offset[i + 1]; ++k) {
      const Index* c = &m.tri_index[3 * std::size_t(m.particle_tri_index[k])];
      sum += (x[c[1]] - x[c[0]]).cross(x[c[2]] - x[c[0]]);
    }
    const Real len = sum.norm();
    normal[i] = len > 0 ? Vec3(sum / len) : Vec3(0, 1, 0);
  });
}

}  // namespace clothsim
