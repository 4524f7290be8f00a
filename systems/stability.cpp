#include "systems/stability.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/csr.h"
#include "systems/parallel.h"
#include "systems/random_force.h"
#include "systems/reduce.h"

namespace clothsim {

Real estimate_omega_max(const Model& m, std::span<const Vec3> x_rest, int max_iterations, Real tolerance) {
  const Index n = m.particle_count;
  // Scratch is local: this runs once at start-up (validate, or the divergence message), never inside step.
  std::vector<Vec3> w(n), y(n), dir(m.spring_count);
  std::vector<Real> inv_sqrt_m(n);
  for (Index i = 0; i < n; ++i) inv_sqrt_m[i] = std::sqrt(m.particle_inv_mass[i]);
  // The spring CSR: the model's, or a local one where the model goes without it (the blocked layout).
  std::vector<Index> own_offset, own_index;
  if (m.particle_spring_offset.empty()) build_particle_springs(m, own_offset, own_index);
  const std::vector<Index>& offset = own_offset.empty() ? m.particle_spring_offset : own_offset;
  const std::vector<Index>& index = own_offset.empty() ? m.particle_spring_index : own_index;
  parallel_over(m.spring_count, 4 * particle_grain, [&](Index s) {
    const Vec3 d = x_rest[m.spring_b[s]] - x_rest[m.spring_a[s]];
    const Real len = d.norm();
    dir[s] = len > 0 ? Vec3(d / len) : Vec3::Zero();
  });
  for (Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) w[i][k] = inv_sqrt_m[i] > 0 ? random_unit(12345, 0, i, k) - 0.5 : 0.0;

  // y = M^-1/2 K M^-1/2 w, gathered per particle: (K u)_i = sum over springs (i, j) of ke n n^T (u_i - u_j).
  auto apply = [&] {
    parallel_over(n, particle_grain, [&](Index i) {
      Vec3 sum = Vec3::Zero();
      if (inv_sqrt_m[i] > 0)
        for (Index k = offset[i]; k < offset[i + 1]; ++k) {
          const Index e = index[k];
          const Index s = e >= 0 ? e : ~e;
          const Index j = e >= 0 ? m.spring_b[s] : m.spring_a[s];
          const Vec3 du = inv_sqrt_m[i] * w[i] - inv_sqrt_m[j] * w[j];
          sum += m.spring_ke[s] * dir[s].dot(du) * dir[s];
        }
      y[i] = inv_sqrt_m[i] * sum;
    });
  };
  Real lambda = 0;
  for (int it = 0; it < max_iterations; ++it) {
    const Real ww = deterministic_sum(n, particle_grain, Real(0), [&](Index i) { return w[i].squaredNorm(); });
    if (!(ww > 0)) return 0;
    apply();
    const Real wy = deterministic_sum(n, particle_grain, Real(0), [&](Index i) { return w[i].dot(y[i]); });
    const Real next = wy / ww;
    const Real yy = deterministic_sum(n, particle_grain, Real(0), [&](Index i) { return y[i].squaredNorm(); });
    if (!(yy > 0)) return 0;
    const Real scale = 1 / std::sqrt(yy);
    parallel_over(n, particle_grain, [&](Index i) { w[i] = scale * y[i]; });
    const bool converged = it > 0 && std::abs(next - lambda) <= tolerance * next;
    lambda = next;
    if (converged) break;
  }
  return std::sqrt(std::max<Real>(lambda, 0));
}

StableSteps stable_steps(Real omega_max) {
  const Real inf = std::numeric_limits<Real>::infinity();
  return {omega_max, omega_max > 0 ? 2 / omega_max : inf, omega_max > 0 ? 2 * std::sqrt(2.0) / omega_max : inf};
}

Real stable_step_limit(const StableSteps& limits, Integrator integrator) {
  switch (integrator) {
    case Integrator::euler: return 0;
    case Integrator::symplectic: return limits.symplectic;
    case Integrator::rk4: return limits.rk4;
    case Integrator::implicit: break;
  }
  return std::numeric_limits<Real>::infinity();
}

Real mechanical_energy(const Model& m, const State& s, std::span<const Vec3> x_start) {
  const Real particles = deterministic_sum(m.particle_count, particle_grain, Real(0), [&](Index i) {
    const Real inv_m = m.particle_inv_mass[i];
    if (!(inv_m > 0)) return Real(0);
    return (0.5 * s.v[i].squaredNorm() - m.gravity.dot(s.x[i] - x_start[i])) / inv_m;
  });
  const Real springs = deterministic_sum(m.spring_count, 4 * particle_grain, Real(0), [&](Index k) {
    const Real stretch = (s.x[m.spring_b[k]] - s.x[m.spring_a[k]]).norm() - m.spring_rest[k];
    return 0.5 * m.spring_ke[k] * stretch * stretch;
  });
  return particles + springs;
}

Real energy_rise_bound(const Model& m, std::span<const Vec3> x_start) {
  Real mass = 0;
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (Index i = 0; i < m.particle_count; ++i) {
    if (m.particle_inv_mass[i] > 0) mass += 1 / m.particle_inv_mass[i];
    lo = lo.cwiseMin(x_start[i]);
    hi = hi.cwiseMax(x_start[i]);
  }
  const Real diagonal = m.particle_count > 0 ? (hi - lo).norm() : 0;
  const Real duration = (m.end_frame - m.start_frame) / m.fps;
  const Real random_speed = std::sqrt(3.0) * m.random.amplitude * duration;
  Real springs = 0;
  for (Index s = 0; s < m.spring_count; ++s) springs += 0.5 * m.spring_ke[s] * std::pow(0.1 * m.spring_rest[s], 2);
  const Real scale = mass * (m.gravity.norm() * diagonal + 0.5 * m.wind_velocity.squaredNorm() +
                             0.5 * random_speed * random_speed) + springs;
  return 10 * scale;
}

}  // namespace clothsim
