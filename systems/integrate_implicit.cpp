#include "systems/integrate_implicit.h"

#include <cmath>

#include "systems/forces.h"
#include "systems/parallel.h"
#include "systems/reduce.h"
#include "systems/spring_jacobian.h"

namespace clothsim {
namespace {

using Sums2 = Eigen::Matrix<Real, 2, 1, Eigen::DontAlign>;

// Each spring's block of A and, on the first solve, its share h^2 df_a/dx_b (v_b - v_a) of the right-hand side
// h^2 (df/dx) v (particle b receives the negative).
void build_spring_terms(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Real h, bool first,
                        Workspace& ws) {
  parallel_over(m.spring_count, 4 * particle_grain, [&](Index s) {
    const Index a = m.spring_a[s], b = m.spring_b[s];
    const SpringJacobian j = spring_jacobian(x[a], x[b], m.spring_rest[s], m.spring_ke[s], m.spring_kd[s]);
    ws.spring_block[s] = spring_system_block(j, h);
    if (first) ws.spring_vec[s] = (h * h) * (j.dfdx * (v[b] - v[a]));
  });
}

// Per particle, gathered over its incident springs (no scatter): the block outside the springs (mass, air
// damping h m c I, wind h k_w A n n^T), the inverse of the whole diagonal block (block-Jacobi), and the
// right-hand side into ws.cg_r. First solve: b = h f + h^2 (df/dx) v (eq. 15-16); later Newton solves:
// b = h f(x_k, v_k) - M dv_k, the backward-Euler residual. ws.f holds accelerations: m a = f for free particles.
// Pinned particles get zero everywhere: the filter S = 0 of Baraff & Witkin §5.3.
void build_particle_terms(const Model& m, Real h, bool first, Workspace& ws) {
  const bool wind = m.wind_strength != 0;
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    const Real inv_m = m.particle_inv_mass[i];
    if (!(inv_m > 0)) {
      ws.cg_diag[i] = Mat3::Zero();
      ws.cg_precond[i] = Mat3::Zero();
      ws.cg_r[i] = Vec3::Zero();
      return;
    }
    const Real mass = 1 / inv_m;
    Mat3 diag = (mass * (1 + h * m.air_damping)) * Mat3::Identity();
    if (wind) diag += (h * m.wind_strength * m.particle_area[i]) * (ws.normal[i] * ws.normal[i].transpose());
    Mat3 block = diag;
    Vec3 kv = Vec3::Zero();
    for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
      const Index e = m.particle_spring_index[k];
      const Index s = e >= 0 ? e : ~e;
      block += ws.spring_block[s];
      if (first) kv += e >= 0 ? ws.spring_vec[s] : Vec3(-ws.spring_vec[s]);
    }
    ws.cg_diag[i] = diag;
    ws.cg_precond[i] = block.inverse();
    ws.cg_r[i] = first ? Vec3(h * mass * ws.f[i] + kv) : Vec3(h * mass * ws.f[i] - mass * ws.dv[i]);
  });
}

// q = A p, gathered per particle: (A p)_i = D_i p_i + sum over springs s = (i, j) of B_s (p_i - p_j).
// p is zero on pinned particles, so their columns drop out; their rows are set to zero.
void apply_system(const Model& m, std::span<const Vec3> x, Real h, ImplicitLayout layout, const Workspace& ws,
                  std::span<const Vec3> p, std::span<Vec3> q) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    if (!(m.particle_inv_mass[i] > 0)) {
      q[i] = Vec3::Zero();
      return;
    }
    Vec3 sum = ws.cg_diag[i] * p[i];
    for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
      const Index e = m.particle_spring_index[k];
      const Index s = e >= 0 ? e : ~e;
      const Index j = e >= 0 ? m.spring_b[s] : m.spring_a[s];
      if (layout == ImplicitLayout::spring_blocks) {
        sum += ws.spring_block[s] * (p[i] - p[j]);
      } else {
        const Index a = m.spring_a[s], b = m.spring_b[s];
        const SpringJacobian jac = spring_jacobian(x[a], x[b], m.spring_rest[s], m.spring_ke[s], m.spring_kd[s]);
        sum += spring_system_block(jac, h) * (p[i] - p[j]);
      }
    }
    q[i] = sum;
  });
}

}  // namespace

CgResult solve_cg(const Model& m, std::span<const Vec3> x, Workspace& ws, Real h, ImplicitLayout layout) {
  const Index n = m.particle_count;
  auto &y = ws.cg_x, &r = ws.cg_r, &p = ws.cg_p, &q = ws.cg_q, &z = ws.cg_z;
  const auto& precond = ws.cg_precond;
  // y0 = 0, so r0 = b; z0 = P r0; p0 = z0.
  const Sums2 start = deterministic_sum(n, particle_grain, Sums2(Sums2::Zero()), [&](Index i) {
    y[i] = Vec3::Zero();
    z[i] = precond[i] * r[i];
    p[i] = z[i];
    return Sums2(r[i].squaredNorm(), r[i].dot(z[i]));
  });
  const Real bb = start[0];
  Real rr = bb, rz = start[1];
  const Real stop = m.cg_tolerance * m.cg_tolerance * bb;
  CgResult res;
  if (!(bb > 0)) return res;
  while (rr > stop && res.iterations < m.cg_max_iterations) {
    apply_system(m, x, h, layout, ws, p, q);
    const Real pq = deterministic_sum(n, particle_grain, Real(0), [&](Index i) { return p[i].dot(q[i]); });
    if (!(pq > 0)) break;  // A is positive definite by construction; this guards round-off at convergence
    const Real alpha = rz / pq;
    const Sums2 next = deterministic_sum(n, particle_grain, Sums2(Sums2::Zero()), [&](Index i) {
      y[i] += alpha * p[i];
      r[i] -= alpha * q[i];
      z[i] = precond[i] * r[i];
      return Sums2(r[i].squaredNorm(), r[i].dot(z[i]));
    });
    const Real beta = next[1] / rz;
    rr = next[0];
    rz = next[1];
    parallel_over(n, particle_grain, [&](Index i) { p[i] = z[i] + beta * p[i]; });
    ++res.iterations;
  }
  res.residual = std::sqrt(rr / bb);
  return res;
}

void integrate_implicit(const Model& m, const State& in, State& out, Workspace& ws, Real h, ImplicitLayout layout) {
  const Index n = m.particle_count;
  Workspace::SolveRecord record;
  for (int k = 0; k < m.newton_iterations; ++k) {
    const bool first = k == 0;
    // Baraff & Witkin linearise about (x0, v0); each Newton correction about the latest iterate (out.x, out.v).
    std::span<const Vec3> x = first ? std::span<const Vec3>(in.x) : std::span<const Vec3>(out.x);
    std::span<const Vec3> v = first ? std::span<const Vec3>(in.v) : std::span<const Vec3>(out.v);
    eval_forces(m, x, v, in.step, ws);
    build_spring_terms(m, x, v, h, first, ws);
    if (first) parallel_over(n, particle_grain, [&](Index i) { ws.dv[i] = Vec3::Zero(); });
    build_particle_terms(m, h, first, ws);
    const CgResult cg = solve_cg(m, x, ws, h, layout);
    record.cg_iterations += cg.iterations;
    record.cg_residual = cg.residual;
    parallel_over(n, particle_grain, [&](Index i) {
      ws.dv[i] += ws.cg_x[i];
      out.v[i] = in.v[i] + ws.dv[i];
      out.x[i] = in.x[i] + h * out.v[i];
    });
  }
  ws.cg_iterations_total += record.cg_iterations;
  if (ws.solve_log.size() < ws.solve_log.capacity()) ws.solve_log.push_back(record);
}

}  // namespace clothsim
