#include "systems/integrate_explicit.h"

#include "systems/parallel.h"

namespace clothsim {

void integrate_euler(std::span<const Vec3> x, std::span<const Vec3> v, std::span<const Vec3> a, Real h,
                     std::span<Vec3> x_out, std::span<Vec3> v_out) {
  parallel_over(Index(x.size()), particle_grain, [&](Index i) {
    const Vec3 vi = v[i];
    x_out[i] = x[i] + h * vi;
    v_out[i] = vi + h * a[i];
  });
}

void integrate_symplectic(std::span<const Vec3> x, std::span<const Vec3> v, std::span<const Vec3> a, Real h,
                          std::span<Vec3> x_out, std::span<Vec3> v_out) {
  parallel_over(Index(x.size()), particle_grain, [&](Index i) {
    const Vec3 vn = v[i] + h * a[i];
    v_out[i] = vn;
    x_out[i] = x[i] + h * vn;
  });
}

}  // namespace clothsim
