#include "systems/cholesky_preconditioner.h"

#include <algorithm>

#include "systems/implicit_system.h"

namespace clothsim {

int refresh_cholesky(const Model& m, Real h, Workspace& ws) {
  const bool stale = ws.cholesky_last_iterations > cholesky_refactor_iterations;
  if (stale) {
    // Stale at its first reuse (a fresh solve, then one with the factor a step old): renew it at each of the
    // next solves, a run that doubles each time this recurs, before trying to reuse one again.
    if (ws.cholesky_solves == 2) {
      ws.cholesky_renew_run = std::clamp(2 * ws.cholesky_renew_run, cholesky_renew_first, cholesky_renew_most);
      ws.cholesky_renew_left = ws.cholesky_renew_run;
    } else {
      ws.cholesky_renew_run = 0;
    }
  }
  const bool due = ws.cholesky_h != h || stale || ws.cholesky_renew_left > 0;
  if (!due) return 0;
  if (ws.cholesky_renew_left > 0) --ws.cholesky_renew_left;
  CholeskyFactor& f = *ws.cholesky;
  cholesky_clear(f);
  // The filter of Baraff & Witkin §5.3 with S = 0: a pinned particle's row and column are the identity's, and
  // its springs add only to their free end's diagonal block.
  for (Index i = 0; i < m.particle_count; ++i) {
    if (!(m.particle_inv_mass[i] > 0)) {
      cholesky_add_diagonal(f, i, Sym3::from(Mat3::Identity()));
      continue;
    }
    Sym3 block = Sym3::from(particle_system_block(m, i, 1 / m.particle_inv_mass[i], h, ws));
    for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
      const Index e = m.particle_spring_index[k];
      block += ws.spring_block[e >= 0 ? e : ~e];
    }
    cholesky_add_diagonal(f, i, block);
  }
  for (Index s = 0; s < m.spring_count; ++s) {
    const Index a = m.spring_a[s], b = m.spring_b[s];
    if (a != b && m.particle_inv_mass[a] > 0 && m.particle_inv_mass[b] > 0)
      cholesky_add_coupling(f, s, ws.spring_block[s], a, b);
  }
  ws.cholesky_h = cholesky_factorize(f) ? h : 0;
  ws.cholesky_last_iterations = 0;
  ws.cholesky_solves = 0;
  return 1;
}

void apply_cholesky(const Model& m, Workspace& ws, std::span<const Vec3> r, std::span<Vec3> z) {
  if (ws.cholesky_h != 0) {
    cholesky_solve(*ws.cholesky, r.data(), z.data());
    return;
  }
  parallel_over(m.particle_count, particle_grain, [&](Index i) { z[i] = ws.cg_precond[i] * r[i]; });
}

}  // namespace clothsim
