#include "systems/integrate_implicit.h"

#include <cmath>
#include <limits>
#include <type_traits>

#include "systems/bend_forces.h"
#include "systems/cholesky_preconditioner.h"
#include "systems/contact_filter.h"
#include "systems/forces.h"
#include "systems/multigrid.h"
#include "systems/parallel.h"
#include "systems/reduce.h"
#include "systems/spring_forces.h"
#include "systems/spring_jacobian.h"

namespace clothsim {
namespace {

using Sums2 = Eigen::Matrix<Real, 2, 1, Eigen::DontAlign>;

// Each spring's block of A, read by every CG product.
void build_spring_blocks(const Model& m, std::span<const Vec3> x, Real h, Workspace& ws) {
  with_spring_blocks(ws, [&](auto& blocks) {
    using Block = typename std::decay_t<decltype(blocks)>::value_type;
    parallel_over(m.spring_count, 4 * particle_grain, [&](Index s) {
      const Index a = m.spring_a[s], b = m.spring_b[s];
      blocks[s] = Block::from(
          spring_system_block(spring_jacobian(x[a], x[b], m.spring_rest[s], m.spring_ke[s], m.spring_kd[s]), h));
    });
  });
}

// Per particle, gathered over its incident springs (no scatter): the inverse of the diagonal block of A
// (block-Jacobi) and the right-hand side into ws.cg_r. First solve: b = h f + h^2 (df/dx) v (eq. 15-16), the
// (df/dx) v term recomputed from each incident spring (spring_dfdx_times; once a step, no per-spring buffer);
// later Newton solves: b = h f(x_k, v_k) - M dv_k, the backward-Euler residual. ws.f holds accelerations: m a = f for free particles.
// Pinned particles get zero everywhere: the filter S = 0 of Baraff & Witkin §5.3.
template <class Blocks>
void build_particle_terms_with(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Real h, bool first,
                               const Blocks& blocks, Workspace& ws) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    const Real inv_m = m.particle_inv_mass[i];
    if (!(inv_m > 0)) {
      ws.cg_precond[i] = Sym3{};
      ws.cg_r[i] = Vec3::Zero();
      return;
    }
    const Real mass = 1 / inv_m;
    Sym3 block = Sym3::from(particle_system_block(m, i, mass, h, ws));
    Vec3 kv = Vec3::Zero();  // ((df/dx) v)_i = sum over springs (i, j) of df_i/dx_j (v_j - v_i)
    for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
      const Index e = m.particle_spring_index[k];
      const Index s = e >= 0 ? e : ~e;
      block += blocks[s];
      if (first) {
        const Index a = m.spring_a[s], b = m.spring_b[s], j = e >= 0 ? b : a;
        kv += spring_dfdx_times(x[a], x[b], m.spring_rest[s], m.spring_ke[s], v[j] - v[i]);
      }
    }
    // Stitches: their diagonal coefficient and (df/dx) v (systems/stitch_forces.h).
    if (m.stitch_count > 0) {
      block += stitch_diagonal(m, ws, i);
      if (first) kv += stitch_dfdx_times(m, ws, i, v);
    }
    // Hinges: h^2 sum u_i u_i^T, and -sum u_i (u . v) (systems/bend_forces.h).
    if (m.hinge_count > 0) {
      block += Sym3::from((h * h) * hinge_diagonal(m, ws.hinge_jac, i));
      if (first) kv -= hinge_row(m, ws.hinge_jac, i, v);
    }
    ws.cg_precond[i] = Sym3::from(block.full().inverse());  // symmetric up to round-off: its lower triangle
    ws.cg_r[i] = first ? Vec3(h * mass * ws.f[i] + (h * h) * kv) : Vec3(h * mass * ws.f[i] - mass * ws.dv[i]);
  });
}

void build_particle_terms(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Real h, bool first,
                          Workspace& ws) {
  with_spring_blocks(ws, [&](const auto& blocks) { build_particle_terms_with(m, x, v, h, first, blocks, ws); });
}

// Whether a probe's squared relative residual rel2 after k iterations, reduced at the same rate up to the cap,
// would come within cholesky_probe_margin times the tolerance. Judged from the second iteration on: the first
// says little about the rate.
bool probe_on_pace(Real rel2, int k, const SolverOptions& opt) {
  if (k < 2) return true;
  const Real goal = cholesky_probe_margin * opt.cg_tolerance;
  return (Real(opt.cg_max_iterations) / Real(k)) * std::log(rel2) <= 2 * std::log(goal);
}

// Preconditioned CG (Shewchuk 1994, B2) from y = 0, stopping at |r| <= tol |b|. The preconditioner z = B r is
// block-Jacobi, applied per particle where needed (z is not stored), or the multigrid cycle or the Cholesky
// solve into ws.cg_q: q = A p is spent once r is updated, and z once it has made the next p, before the next
// product (one particle vector less). Filtered, every search direction and product is projected as Baraff &
// Witkin's modified PCG does (S B S as the preconditioner); r arrives filtered.
template <Preconditioner Kind>
CgResult run_cg(const Model& m, const SolverOptions& opt, std::span<const Vec3> x, Workspace& ws, Real h,
                ImplicitLayout layout, CgStart from) {
  constexpr bool cycle = Kind != Preconditioner::jacobi;
  auto precondition = [&](std::span<const Vec3> r_in, std::span<Vec3> z_out) {
    if constexpr (Kind == Preconditioner::multigrid) apply_multigrid(m, x, h, layout, ws, r_in, z_out);
    else apply_cholesky(m, ws, r_in, z_out);
  };
  const Index n = m.particle_count;
  auto &y = ws.cg_x, &r = ws.cg_r, &p = ws.cg_p, &q = ws.cg_q, &z = ws.cg_q;
  const auto& precond = ws.cg_precond;
  auto z_at = [&](Index i) -> Vec3 {
    if constexpr (cycle) return z[i];
    else return precond[i] * r[i];
  };
  if constexpr (cycle) precondition(r, z);
  // y0 = 0, so r0 = b (or y0 and its residual r0 when resuming); z0 = B r0; p0 = z0.
  const Sums2 start = deterministic_sum(n, particle_grain, Sums2(Sums2::Zero()), [&](Index i) {
    if (!(from.reference > 0)) y[i] = Vec3::Zero();
    p[i] = z_at(i);
    return Sums2(r[i].squaredNorm(), r[i].dot(p[i]));
  });
  if (from.filtered) filter_held(ws, p);
  const Real bb = from.reference > 0 ? from.reference * from.reference : start[0];
  Real rr = start[0], rz = start[1];
  const Real stop = opt.cg_tolerance * opt.cg_tolerance * bb;
  CgResult res;
  res.rhs_norm = std::sqrt(bb);
  // Below the smallest normal double a dot product keeps only a few significant bits, and alpha = rz / pq built
  // from two such numbers can be off by orders of magnitude: a motion decaying to exactly zero (the undamped chain
  // of the stability study at h w = 44) blew up to 1e53 J that way. Such a right-hand side or search direction is
  // zero for the solve's purpose.
  constexpr Real smallest_normal = std::numeric_limits<Real>::min();
  if (!(rr >= smallest_normal)) return res;
  while (rr > stop && res.iterations < opt.cg_max_iterations) {
    apply_system(m, x, h, layout, ws, p, q);
    if (from.filtered) filter_held(ws, q);
    const Real pq = deterministic_sum(n, particle_grain, Real(0), [&](Index i) { return p[i].dot(q[i]); });
    // A is positive definite by construction; this guards round-off at convergence and subnormal directions.
    if (!(pq >= smallest_normal && rz >= smallest_normal)) break;
    const Real alpha = rz / pq;
    const Sums2 next = deterministic_sum(n, particle_grain, Sums2(Sums2::Zero()), [&](Index i) {
      y[i] += alpha * p[i];
      r[i] -= alpha * q[i];
      return Sums2(r[i].squaredNorm(), cycle ? 0 : r[i].dot(z_at(i)));
    });
    rr = next[0];
    ++res.iterations;
    if (!(rr > stop)) break;  // converged: the next direction (and its cycle) would go unused
    if (from.probe && !probe_on_pace(rr / bb, res.iterations, opt)) break;
    Real rz_next = next[1];
    if constexpr (cycle) {
      precondition(r, z);
      rz_next = deterministic_sum(n, particle_grain, Real(0), [&](Index i) { return r[i].dot(z[i]); });
    }
    const Real beta = rz_next / rz;
    rz = rz_next;
    parallel_over(n, particle_grain, [&](Index i) { p[i] = z_at(i) + beta * p[i]; });
    if (from.filtered) filter_held(ws, p);
  }
  res.residual = std::sqrt(rr / bb);
  return res;
}

}  // namespace

CgResult solve_cg(const Model& m, const SolverOptions& opt, std::span<const Vec3> x, Workspace& ws, Real h,
                  ImplicitLayout layout, CgStart from) {
  switch (opt.preconditioner) {
    case Preconditioner::multigrid: return run_cg<Preconditioner::multigrid>(m, opt, x, ws, h, layout, from);
    case Preconditioner::cholesky: {
      // A factor kept from an earlier solve gets cholesky_refactor_iterations; a solve it has not finished by
      // then is restarted with a fresh factor from where it got to (systems/cholesky_preconditioner.h).
      const bool reused = ws.cholesky_solves > 0 && ws.cholesky_h == h;
      SolverOptions probe = opt;
      if (reused) probe.cg_max_iterations = std::min(opt.cg_max_iterations, cholesky_refactor_iterations);
      CgResult res = run_cg<Preconditioner::cholesky>(m, probe, x, ws, h, layout,
                                                      {from.filtered, from.reference, reused});
      if (reused && !(res.residual <= opt.cg_tolerance)) {
        const int spent = res.iterations;
        const int renewed = renew_stale_cholesky(m, h, ws);
        const Real reference = from.reference > 0 ? from.reference : res.rhs_norm;
        res = run_cg<Preconditioner::cholesky>(m, opt, x, ws, h, layout, {from.filtered, reference});
        res.iterations += spent;
        res.factorizations = renewed;
      }
      ++ws.cholesky_solves;
      return res;
    }
    case Preconditioner::jacobi: break;
  }
  return run_cg<Preconditioner::jacobi>(m, opt, x, ws, h, layout, from);
}

StepResult integrate_implicit(const Model& m, const SolverOptions& opt, const State& in, State& out, Workspace& ws,
                              Real h, ImplicitLayout layout) {
  const Index n = m.particle_count;
  // The step's velocity change. With one solve it is that solve's y itself: 0 + y is y bit for bit, since CG
  // builds y from +0 by additions alone and so never makes -0. Newton corrections add into ws.dv.
  const bool one_solve = opt.newton_iterations == 1;
  // A workspace made for one solve has no dv; stepping it with more Newton iterations grows it here, not out of bounds.
  if (!one_solve && ws.dv.size() != std::size_t(n)) ws.dv.assign(std::size_t(n), Vec3::Zero());
  std::span<Vec3> dv = one_solve ? std::span<Vec3>(ws.cg_x) : std::span<Vec3>(ws.dv);
  StepResult result;
  SolveRecord& record = result.solve;
  Real last_residual = 0;  // |b| of the previous Newton correction's right-hand side (the backward-Euler residual)
  const bool filtered = prepare_contact_filter(m, in, ws);
  for (int k = 0; k < opt.newton_iterations; ++k) {
    const bool first = k == 0;
    // Baraff & Witkin linearise about (x0, v0); each Newton correction about the latest iterate (out.x, out.v).
    std::span<const Vec3> x = first ? std::span<const Vec3>(in.x) : std::span<const Vec3>(out.x);
    std::span<const Vec3> v = first ? std::span<const Vec3>(in.v) : std::span<const Vec3>(out.v);
    result.counts.add(eval_forces(m, x, v, in.time, ws));
    build_spring_blocks(m, x, h, ws);
    if (m.stitch_count > 0) build_stitch_blocks(m, x, v, h, ws);
    if (m.hinge_count > 0) build_hinge_jacobians(m, x, ws.hinge_jac);
    if (first && !one_solve) parallel_over(n, particle_grain, [&](Index i) { dv[i] = Vec3::Zero(); });
    build_particle_terms(m, x, v, h, first, ws);
    if (!first) {
      const Real residual = std::sqrt(
          deterministic_sum(n, particle_grain, Real(0), [&](Index i) { return ws.cg_r[i].squaredNorm(); }));
      if (k >= 2 && residual > last_residual) record.newton_diverged = true;
      last_residual = residual;
    }
    if (filtered) start_filtered_solve(ws);
    if (opt.preconditioner == Preconditioner::multigrid) build_multigrid_operators(m, h, ws);
    if (opt.preconditioner == Preconditioner::cholesky) record.factorizations += refresh_cholesky(m, h, ws);
    const CgResult cg = solve_cg(m, opt, x, ws, h, layout, {filtered});
    if (filtered) finish_filtered_solve(m, x, h, layout, ws);
    record.factorizations += cg.factorizations;
    record.cg_iterations += cg.iterations;
    record.cg_residual = cg.residual;
    if (!(cg.residual <= opt.cg_tolerance)) record.converged = false;
    parallel_over(n, particle_grain, [&](Index i) {
      if (!one_solve) dv[i] += ws.cg_x[i];
      out.v[i] = in.v[i] + dv[i];
      out.x[i] = in.x[i] + h * out.v[i];
    });
  }
  if (filtered) apply_held_friction(m, in, out, ws, h);
  result.counts.cg_iterations = record.cg_iterations;
  result.failed = record.failed();
  return result;
}

}  // namespace clothsim
