#pragma once
// Hooke springs with damping along the spring (Provot 1995 eq. 2-3; Baraff & Witkin 1998 §4).
#include <cmath>
#include <span>

#include "core/model.h"

namespace clothsim {

// Force on particle a of a spring a-b: f = [ke (|d| - rest) + kd (v_b - v_a).d/|d|] d/|d|, d = x_b - x_a.
// Particle b receives -f. A zero-length spring has no direction and exerts nothing.
inline Vec3 spring_force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb, Real rest, Real ke,
                         Real kd) {
  const Vec3 d = xb - xa;
  const Real len = d.norm();
  if (!(len > 0)) return Vec3::Zero();
  const Vec3 n = d / len;
  return (ke * (len - rest) + kd * (vb - va).dot(n)) * n;
}

// f[i] = sum of the spring forces on particle i (overwrites f), in the model's spring_layout.
void eval_springs(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f,
                  std::span<Vec3> spring_scratch);
// The two layouts, callable directly so the benchmark can compare them.
void eval_springs_gather(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f);
void eval_springs_two_phase(const Model& model, std::span<const Vec3> x, std::span<const Vec3> v,
                            std::span<Vec3> f, std::span<Vec3> spring_force);
// The second phase of two_phase: f[i] = sum of the per-spring forces on particle i, in CSR order.
void gather_spring_forces(const Model& model, std::span<const Vec3> spring_force, std::span<Vec3> f);

// Largest strain (|d| - rest)/rest over all springs: a maximum, so exact at any thread count.
Real max_spring_strain(const Model& model, std::span<const Vec3> x);

}  // namespace clothsim
