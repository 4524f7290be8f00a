#include "systems/stability.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>
#include <limits>

#include "core/csr.h"
#include "systems/bend_forces.h"
#include "systems/parallel.h"
#include "systems/random_force.h"
#include "systems/reduce.h"
#include "systems/spring_forces.h"
#include "systems/diagnostics.h"
#include "systems/step.h"

namespace clothsim {

namespace {

// Power iteration on M^-1/2 A M^-1/2, A = sum over springs of coef (n n^T, or I for a spring of zero length) in
// K's block pattern. Scratch is local: this runs once at start-up (validate, auto step, the divergence message),
// never inside step.
class SpringOperator {
 public:
  SpringOperator(const Model& m, std::span<const Vec3> x_rest) : m_(m), n_(m.particle_count) {
    inv_sqrt_m_.resize(n_);
    for (Index i = 0; i < n_; ++i) inv_sqrt_m_[i] = std::sqrt(m.particle_inv_mass[i]);
    // The spring CSR: the model's, or a local one where the model goes without it (the blocked layout).
    if (m.particle_spring_offset.empty()) build_particle_springs(m, own_offset_, own_index_);
    dir_.resize(m.spring_count);
    parallel_over(m.spring_count, 4 * particle_grain, [&](Index s) {
      const Vec3 d = x_rest[m.spring_b[s]] - x_rest[m.spring_a[s]];
      const Real len = d.norm();
      dir_[s] = len > 0 ? Vec3(d / len) : Vec3::Zero();
    });
  }

  // y = M^-1/2 A M^-1/2 w, gathered per particle: (A u)_i = sum over springs (i, j) of coef n n^T (u_i - u_j).
  void apply(const ParamField& coef, const std::vector<Vec3>& w, std::vector<Vec3>& y) const {
    const std::vector<Index>& offset = own_offset_.empty() ? m_.particle_spring_offset : own_offset_;
    const std::vector<Index>& index = own_offset_.empty() ? m_.particle_spring_index : own_index_;
    parallel_over(n_, particle_grain, [&](Index i) {
      Vec3 sum = Vec3::Zero();
      if (inv_sqrt_m_[i] > 0)
        for (Index k = offset[i]; k < offset[i + 1]; ++k) {
          const Index e = index[k];
          const Index s = e >= 0 ? e : ~e;
          const Index j = e >= 0 ? m_.spring_b[s] : m_.spring_a[s];
          const Vec3 du = inv_sqrt_m_[i] * w[i] - inv_sqrt_m_[j] * w[j];
          const Vec3& n = dir_[s];
          sum += coef[s] * (n.squaredNorm() > 0 ? Vec3(n.dot(du) * n) : du);
        }
      y[i] = inv_sqrt_m_[i] * sum;
    });
  }

  Real dot(const std::vector<Vec3>& a, const std::vector<Vec3>& b) const {
    return deterministic_sum(n_, particle_grain, Real(0), [&](Index i) { return a[i].dot(b[i]); });
  }

  // Largest eigenvalue (Rayleigh quotient) of the operator with coef; w ends as its unit eigenvector.
  Real top(const ParamField& coef, std::vector<Vec3>& w, int max_iterations, Real tolerance) const {
    std::vector<Vec3> y(n_);
    w.assign(n_, Vec3::Zero());
    for (Index i = 0; i < n_; ++i)
      for (int k = 0; k < 3; ++k) w[i][k] = inv_sqrt_m_[i] > 0 ? random_unit(12345, 0, i, k) - 0.5 : 0.0;
    Real lambda = 0;
    for (int it = 0; it < max_iterations; ++it) {
      const Real ww = dot(w, w);
      if (!(ww > 0)) return 0;
      apply(coef, w, y);
      const Real next = dot(w, y) / ww;
      const Real yy = dot(y, y);
      if (!(yy > 0)) return 0;
      const Real scale = 1 / std::sqrt(yy);
      parallel_over(n_, particle_grain, [&](Index i) { w[i] = scale * y[i]; });
      const bool converged = it > 0 && std::abs(next - lambda) <= tolerance * next;
      lambda = next;
      if (converged) break;
    }
    return std::max<Real>(lambda, 0);
  }

  // w^T A w / w^T w.
  Real rayleigh(const ParamField& coef, const std::vector<Vec3>& w) const {
    std::vector<Vec3> y(n_);
    const Real ww = dot(w, w);
    if (!(ww > 0)) return 0;
    apply(coef, w, y);
    return std::max<Real>(dot(w, y) / ww, 0);
  }

 private:
  const Model& m_;
  Index n_;
  std::vector<Real> inv_sqrt_m_;
  std::vector<Index> own_offset_, own_index_;
  std::vector<Vec3> dir_;
};

constexpr int mode_iterations = 2000;
constexpr Real mode_tolerance = 1e-7;

// Largest stable h of a one-step method with amplification R(z) at z = h lambda, lambda the roots of
// s^2 + gamma s + omega^2: bisection on the first h where |R| exceeds 1.
template <class Amplification>
Real first_unstable_step(Real omega, Real gamma, Amplification R) {
  using C = std::complex<Real>;
  const C root = std::sqrt(C(gamma * gamma - 4 * omega * omega, 0));
  const C l1 = 0.5 * (-gamma + root), l2 = 0.5 * (-gamma - root);
  const Real scale = std::max(std::abs(l1), std::abs(l2));
  if (!(scale > 0)) return std::numeric_limits<Real>::infinity();
  auto stable = [&](Real h) { return std::abs(R(h * l1)) <= 1 + 1e-12 && std::abs(R(h * l2)) <= 1 + 1e-12; };
  // Every RK4-stable z has |z| < 3; scan for the first unstable step, then bisect.
  constexpr int scan = 512;
  Real lo = 0, hi = 4 / scale;
  for (int k = 1; k <= scan; ++k) {
    const Real h = (4 / scale) * k / scan;
    if (!stable(h)) { hi = h; break; }
    lo = h;
  }
  for (int it = 0; it < 60; ++it) {
    const Real mid = 0.5 * (lo + hi);
    (stable(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

Real estimate_omega_max(const Model& m, std::span<const Vec3> x_rest, int max_iterations, Real tolerance) {
  std::vector<Vec3> w;
  return std::sqrt(SpringOperator(m, x_rest).top(m.spring_ke, w, max_iterations, tolerance));
}

DampedModes estimate_modes(const Model& m, std::span<const Vec3> x_rest) {
  const SpringOperator op(m, x_rest);
  // Damping that acts on every particle alone: air (c v) and the wind's k_w A n.(v) n, at most k_w A / m.
  Real diagonal = m.air_damping;
  Real wind = 0;
  if (m.wind_strength != 0 && !m.particle_area.empty())
    for (Index i = 0; i < m.particle_count; ++i)
      wind = std::max(wind, std::abs(m.wind_strength) * m.particle_area[i] * m.particle_inv_mass[i]);
  diagonal += wind;
  DampedModes d;
  std::vector<Vec3> w;
  d.omega_max = std::sqrt(op.top(m.spring_ke, w, mode_iterations, mode_tolerance));
  d.gamma_of_stiff = op.rayleigh(m.spring_kd, w) + diagonal;
  d.gamma_max = op.top(m.spring_kd, w, mode_iterations, mode_tolerance) + diagonal;
  d.omega_of_damped = std::sqrt(op.rayleigh(m.spring_ke, w));
  Real ratio = std::numeric_limits<Real>::infinity();
  for (Index s = 0; s < m.spring_count; ++s)
    if (m.spring_ke[s] > 0 && m.particle_inv_mass[m.spring_a[s]] + m.particle_inv_mass[m.spring_b[s]] > 0)
      ratio = std::min(ratio, m.spring_kd[s] / m.spring_ke[s]);
  d.euler_floor = ratio + (d.omega_max > 0 ? m.air_damping / (d.omega_max * d.omega_max) : 0);
  return d;
}

Real mode_step_limit(Integrator integrator, Real omega, Real gamma) {
  const Real inf = std::numeric_limits<Real>::infinity();
  using C = std::complex<Real>;
  switch (integrator) {
    case Integrator::euler: {
      if (gamma < 2 * omega) return omega > 0 ? gamma / (omega * omega) : inf;
      const Real rate = 0.5 * (gamma + std::sqrt(gamma * gamma - 4 * omega * omega));
      return rate > 0 ? 2 / rate : inf;
    }
    case Integrator::symplectic: {
      const Real denom = gamma + std::sqrt(gamma * gamma + 4 * omega * omega);
      return denom > 0 ? 4 / denom : inf;
    }
    case Integrator::rk4:
      return first_unstable_step(omega, gamma, [](C z) { return 1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6 + z / 24.0))); });
    case Integrator::implicit: break;
  }
  return inf;
}

Real mode_amplification(Integrator integrator, Real omega, Real gamma, Real h) {
  using C = std::complex<Real>;
  const C root = std::sqrt(C(gamma * gamma - 4 * omega * omega, 0));
  const C z1 = h * 0.5 * (-gamma + root), z2 = h * 0.5 * (-gamma - root);
  switch (integrator) {
    case Integrator::euler: return std::max(std::abs(1.0 + z1), std::abs(1.0 + z2));
    case Integrator::rk4: {
      auto R = [](C z) { return 1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6 + z / 24.0))); };
      return std::max(std::abs(R(z1)), std::abs(R(z2)));
    }
    case Integrator::symplectic: {
      // z^2 - T z + D with T = 2 - h^2 omega^2 - h gamma, D = 1 - h gamma.
      const Real T = 2 - h * h * omega * omega - h * gamma, D = 1 - h * gamma;
      const C disc = std::sqrt(C(T * T - 4 * D, 0));
      return std::max(std::abs(0.5 * (T + disc)), std::abs(0.5 * (T - disc)));
    }
    case Integrator::implicit: break;
  }
  return 0;
}

StableSteps stable_steps(const DampedModes& d) {
  auto limit = [&](Integrator i) {
    return std::min(mode_step_limit(i, d.omega_max, d.gamma_of_stiff),
                    mode_step_limit(i, d.omega_of_damped, d.gamma_max));
  };
  return {d.omega_max, d.gamma_max, std::min(limit(Integrator::euler), d.euler_floor), limit(Integrator::symplectic),
          limit(Integrator::rk4)};
}

StableSteps stable_steps(Real omega_max) {
  const Real inf = std::numeric_limits<Real>::infinity();
  return {omega_max, 0, omega_max > 0 ? 0 : inf, omega_max > 0 ? 2 / omega_max : inf,
          omega_max > 0 ? 2 * std::sqrt(2.0) / omega_max : inf};
}

Real stable_step_limit(const StableSteps& limits, Integrator integrator) {
  switch (integrator) {
    case Integrator::euler: return std::min(limits.euler, limits.hinges);
    case Integrator::symplectic: return std::min(limits.symplectic, limits.hinges);
    case Integrator::rk4: return std::min(limits.rk4, limits.hinges);
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
  // Bending hinges store energy too; a model without them keeps the sum it always had (same bytes).
  if (m.hinge_count > 0) return particles + springs + hinge_potential_energy(m, s.x);
  return particles + springs;
}

Real energy_rise_bound(const Model& m, std::span<const Vec3> x_start, Real duration) {
  Real mass = 0;
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (Index i = 0; i < m.particle_count; ++i) {
    if (m.particle_inv_mass[i] > 0) mass += 1 / m.particle_inv_mass[i];
    lo = lo.cwiseMin(x_start[i]);
    hi = hi.cwiseMax(x_start[i]);
  }
  const Real diagonal = m.particle_count > 0 ? (hi - lo).norm() : 0;
  const Real random_speed = std::sqrt(3.0) * m.random.amplitude * duration;
  Real springs = 0;
  for (Index s = 0; s < m.spring_count; ++s) springs += 0.5 * m.spring_ke[s] * std::pow(0.1 * m.spring_rest[s], 2);
  const Real scale = mass * (m.gravity.norm() * diagonal + 0.5 * m.wind_velocity.squaredNorm() +
                             0.5 * random_speed * random_speed) + springs;
  return 10 * scale;
}

bool run_diverges(const Model& m, const SimOptions& o, const State& start, Real h, std::int64_t steps) {
  const Real e0 = mechanical_energy(m, start, start.x), bound = energy_rise_bound(m, start.x, o.seconds());
  const std::int64_t per_frame = std::max<std::int64_t>(1, std::llround(1 / (o.fps * h)));
  Real frame_strain = max_spring_strain(m, start.x);
  State s = start, scratch = start;
  Workspace ws = make_workspace(m, o);
  for (std::int64_t k = 0; k < steps; ++k) {
    step(m, o, s, scratch, ws, h);
    std::swap(s, scratch);
    if (!state_is_finite(s) || !(mechanical_energy(m, s, start.x) - e0 <= bound)) return true;
    if ((k + 1) % per_frame == 0 || k + 1 == steps) {
      const Real strain = max_spring_strain(m, s.x);
      if (strain - frame_strain > frame_strain_jump) return true;
      frame_strain = strain;
    }
  }
  return false;
}

}  // namespace clothsim
