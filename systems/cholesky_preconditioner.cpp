#include "systems/cholesky_preconditioner.h"

#include <algorithm>
#include <array>
#include <atomic>

#include "core/blas_kernel.h"
#include "systems/contact_filter.h"
#include "systems/implicit_system.h"
#include "systems/parallel.h"
#include "systems/stitch_forces.h"

namespace clothsim {

namespace {

// Runs job(k) for each piece of the factor: handed out to free threads where the BLAS allows calls at once
// (core/blas_kernel.h), one after the other where it does not. The same bytes either way.
template <class Job>
void for_each_piece(CholeskyFactor& f, Job&& job) {
  const Index pieces = cholesky_piece_count(f);
  if (blas_calls_may_overlap()) {
    parallel_hand_out(pieces, job);
  } else {
    for (Index k = 0; k < pieces; ++k) job(k);
  }
}

// Piece k's matrix, its values set from the step's terms; ws.spring_block_f64 (the Cholesky preconditioner keeps
// the spring blocks in double: core/model.h) and the particle terms must be current.
// Each entry gets its terms in the same order as a fill of the whole matrix would add them (diagonal, springs,
// stitches, hinges, each in ascending order), so the values do not depend on how the pieces are shared out.
void fill_piece(const Model& m, Real h, Workspace& ws, Index k) {
  CholeskyFactor& f = *ws.cholesky;
  cholesky_clear_piece(f, k);
  // The filter of Baraff & Witkin §5.3 with S = 0: a pinned particle's row and column are the identity's, and
  // its springs add only to their free end's diagonal block.
  for (const Index i : cholesky_piece_particles(f, k)) {
    if (!(m.particle_inv_mass[i] > 0)) {
      cholesky_add_diagonal(f, i, Sym3::from(Mat3::Identity()));
      continue;
    }
    Sym3 block = Sym3::from(particle_system_block(m, i, 1 / m.particle_inv_mass[i], h, ws));
    for (Index j = m.particle_spring_offset[i]; j < m.particle_spring_offset[i + 1]; ++j) {
      const Index e = m.particle_spring_index[j];
      block += ws.spring_block_f64[e >= 0 ? e : ~e];
    }
    block += hold_block(ws, i, block);
    cholesky_add_diagonal(f, i, block);
  }
  for (const Index s : cholesky_piece_springs(f, k)) {
    const Index a = m.spring_a[s], b = m.spring_b[s];
    if (a != b && m.particle_inv_mass[a] > 0 && m.particle_inv_mass[b] > 0)
      cholesky_add_coupling(f, s, ws.spring_block_f64[s], a, b);
  }
  // Stitches: c_u c_v (h Kv + h^2 Kx) between their particles u, v (systems/stitch_forces.h), the same terms
  // the CG's product applies; without them the factor of a sewn garment misses its seams and CG stalls. A slack
  // thread's zero blocks stay in the pattern, which is fixed for the run.
  for (const Index s : cholesky_piece_stitches(f, k)) {
    const std::array<Index, 3> p = stitch_particles(m, s);
    const std::array<Real, 3> c = stitch_coefficients(m.stitch_w[s]);
    const Mat3 coef = ws.stitch_block[s].full();
    for (int u = 0; u < 3; ++u)
      for (int v = 0; v < 3; ++v) {
        if (!(m.particle_inv_mass[p[u]] > 0) || !(m.particle_inv_mass[p[v]] > 0)) continue;
        const Mat3 block = (c[u] * c[v]) * coef;
        if (p[u] == p[v]) cholesky_add_diagonal(f, p[u], Sym3::from(block));
        else if (u < v) cholesky_add_block(f, p[u], p[v], block);
      }
  }
  // Hinges: h^2 u_a u_b^T between their particles a, b (systems/bend_forces.h), as in the CG's product.
  for (const Index hg : cholesky_piece_hinges(f, k)) {
    const std::array<Index, 4> p = hinge_particles(m, hg);
    const Vec3* u = &ws.hinge_jac[4 * std::size_t(hg)];
    for (int a = 0; a < 4; ++a) {
      if (!(m.particle_inv_mass[p[a]] > 0)) continue;
      cholesky_add_diagonal(f, p[a], Sym3::from((h * h) * (u[a] * u[a].transpose())));
      for (int b = a + 1; b < 4; ++b)
        if (m.particle_inv_mass[p[b]] > 0) cholesky_add_block(f, p[a], p[b], (h * h) * (u[a] * u[b].transpose()));
    }
  }
}

// Numeric refactorisation of the step's matrix. The pieces (core/cholesky_factor.h) are filled and factored on
// whichever thread is free, the longest first, where the BLAS allows calls at once.
void factor_now(const Model& m, Real h, Workspace& ws) {
  std::atomic<bool> factored{true};
  for_each_piece(*ws.cholesky, [&](Index k) {
    fill_piece(m, h, ws, k);
    if (!cholesky_factorize_piece(*ws.cholesky, k)) factored = false;
  });
  ws.cholesky_h = factored ? h : 0;
  ws.cholesky_solves = 0;
}

}  // namespace

int refresh_cholesky(const Model& m, Real h, Workspace& ws) {
  if (ws.cholesky_h == h && ws.cholesky_renewal.left == 0) return 0;
  if (ws.cholesky_renewal.left > 0) --ws.cholesky_renewal.left;
  factor_now(m, h, ws);
  return 1;
}

int renew_stale_cholesky(const Model& m, Real h, Workspace& ws) {
  // Stale at its first reuse (one solve with it fresh, this one with it a solve old): renew it before each of
  // the next solves, a run that doubles each time this recurs; a factor that served a reuse ends the runs.
  if (ws.cholesky_solves == 1) {
    ws.cholesky_renewal.run = std::clamp(2 * ws.cholesky_renewal.run, cholesky_renew_first, cholesky_renew_most);
    ws.cholesky_renewal.left = ws.cholesky_renewal.run;
  } else {
    ws.cholesky_renewal.run = 0;
  }
  factor_now(m, h, ws);
  return 1;
}

void forget_cholesky_factor(Workspace& ws) {
  ws.cholesky_h = 0;
  ws.cholesky_solves = 0;
}

void apply_cholesky(const Model& m, Workspace& ws, std::span<const Vec3> r, std::span<Vec3> z) {
  if (ws.cholesky_h != 0) {
    for_each_piece(*ws.cholesky, [&](Index k) { cholesky_solve_piece(*ws.cholesky, k, r.data(), z.data()); });
    return;
  }
  parallel_over(m.particle_count, particle_grain, [&](Index i) { z[i] = ws.cg_precond[i] * r[i]; });
}

}  // namespace clothsim
