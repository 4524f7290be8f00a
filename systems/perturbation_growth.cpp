#include "systems/perturbation_growth.h"

#include <cmath>
#include <limits>

#include "systems/diagnostics.h"
#include "systems/parallel.h"
#include "systems/random_force.h"
#include "systems/reduce.h"
#include "systems/step.h"

namespace clothsim {

namespace {

constexpr Real twin_offset = 1e-9;  // m, small enough that the twin's deviation stays linear within a window

Real deviation(const Model& m, const State& a, const State& b) {
  const Real kinetic = deterministic_sum(m.particle_count, particle_grain, Real(0), [&](Index i) {
    const Real inv_m = m.particle_inv_mass[i];
    return inv_m > 0 ? (a.v[i] - b.v[i]).squaredNorm() / inv_m : Real(0);
  });
  const Real elastic = deterministic_sum(m.spring_count, 4 * particle_grain, Real(0), [&](Index s) {
    const Real la = (a.x[m.spring_b[s]] - a.x[m.spring_a[s]]).norm();
    const Real lb = (b.x[m.spring_b[s]] - b.x[m.spring_a[s]]).norm();
    return m.spring_ke[s] * (la - lb) * (la - lb);
  });
  return std::sqrt(kinetic + elastic);
}

}  // namespace

std::vector<Real> perturbation_growth(const Model& m, const SimOptions& o, const State& start, Real h,
                                      std::int64_t steps, int windows) {
  State base = start, twin = start, scratch = start;
  for (Index i = 0; i < m.particle_count; ++i)
    if (m.particle_inv_mass[i] > 0)
      for (int k = 0; k < 3; ++k) twin.x[i][k] += twin_offset * (2 * random_unit(4242, 0, i, k) - 1);
  const Real start_deviation = deviation(m, base, twin);
  std::vector<Real> growth;
  if (!(start_deviation > 0) || windows < 1) return growth;
  Workspace ws = make_workspace(m, o);
  const std::int64_t per_window = std::max<std::int64_t>(1, steps / windows);
  for (int w = 0; w < windows; ++w) {
    for (std::int64_t k = 0; k < per_window; ++k) {
      step(m, o, base, scratch, ws, h);
      std::swap(base, scratch);
      step(m, o, twin, scratch, ws, h);
      std::swap(twin, scratch);
    }
    const Real d = deviation(m, base, twin);
    if (!state_is_finite(base) || !state_is_finite(twin) || !std::isfinite(d)) {
      growth.push_back(std::numeric_limits<Real>::infinity());
      break;
    }
    growth.push_back(std::log(d / start_deviation));
    // Back to the start deviation along the same direction (a deviation of 0 stays 0: the twin has merged).
    const Real scale = d > 0 ? start_deviation / d : 0;
    parallel_over(m.particle_count, particle_grain, [&](Index i) {
      twin.x[i] = base.x[i] + scale * (twin.x[i] - base.x[i]);
      twin.v[i] = base.v[i] + scale * (twin.v[i] - base.v[i]);
    });
  }
  return growth;
}

std::vector<Real> growth_over_half_step(const Model& m, const SimOptions& o, const State& start, Real h,
                                        std::int64_t steps, int windows) {
  const std::int64_t per_window = std::max<std::int64_t>(1, steps / std::max(windows, 1));
  std::vector<Real> growth = perturbation_growth(m, o, start, h, per_window * windows, windows);
  const std::vector<Real> half = perturbation_growth(m, o, start, h / 2, 2 * per_window * windows, windows);
  for (std::size_t w = 0; w < growth.size(); ++w)
    if (std::isfinite(growth[w])) growth[w] -= w < half.size() ? half[w] : growth[w];
  return growth;
}

bool grows_exponentially(std::span<const Real> g, Real factor) {
  if (g.empty()) return false;
  if (std::isinf(g.back()) && g.back() > 0) return true;  // a state stopped being finite
  const std::size_t half = g.size() / 2;
  Real total = 0;
  for (std::size_t w = half; w < g.size(); ++w) {
    if (!(g[w] >= 0)) return false;
    total += g[w];
  }
  return total >= std::log(factor);
}

}  // namespace clothsim
