#pragma once
// The matrix of the backward-Euler step, A = M - h df/dv - h^2 df/dx (Baraff & Witkin 1998 eq. 15-16), as the
// CG and the multigrid preconditioner apply it: a 3x3 block per particle outside the springs, and each spring's
// symmetric block B_s, so (A p)_i = G_i p_i + sum over springs s = (i, j) of B_s (p_i - p_j), plus the stitches'
// and the dihedral hinges' terms (h^2 u u^T per hinge, systems/bend_forces.h). Pinned particles
// are filtered out (their rows and columns are zero; Baraff & Witkin §5.3 with S = 0).
#include <span>
#include <type_traits>

#include "core/model.h"
#include "systems/bend_forces.h"
#include "systems/parallel.h"
#include "systems/spring_jacobian.h"
#include "systems/stitch_forces.h"

namespace clothsim {

// How CG applies the matrix (docs/performance.md, "Implicit integration", compares them).
enum class ImplicitLayout {
  spring_blocks,  // the h kd n n^T + h^2 df/dx block of each spring built once per solve, read by every CG product
  recompute,      // matrix-free: each CG product recomputes the spring blocks from the positions
};

// The block of A outside the springs: mass and air damping (m (1 + h c)) and wind h k_w A n n^T.
inline Mat3 particle_system_block(const Model& m, Index i, Real mass, Real h, const Workspace& ws) {
  Mat3 block = (mass * (1 + h * m.air_damping)) * Mat3::Identity();
  if (m.wind_strength != 0) block += (h * m.wind_strength * m.particle_area[i]) * (ws.normal[i] * ws.normal[i].transpose());
  return block;
}

// That block applied to p.
inline Vec3 apply_particle_block(const Model& m, Index i, Real mass, Real h, const Workspace& ws, const Vec3& p) {
  Vec3 q = (mass * (1 + h * m.air_damping)) * p;
  if (m.wind_strength != 0) q += (h * m.wind_strength * m.particle_area[i] * ws.normal[i].dot(p)) * ws.normal[i];
  return q;
}

// Row i of A p without the stitches and hinges (add_extra_row below), gathered over the particle's incident springs
// (no scatter); p must be zero on pinned particles, so their columns drop out. x are the positions the springs are
// linearised about (the recompute layout). The layout is a template argument: callers choose it once, outside
// their loops over particles and springs.
// The spring blocks kept this run (core/model.h): body(ws.spring_block_f64) or body(ws.spring_block_f32), const
// as ws is.
template <class Ws, class Body>
inline void with_spring_blocks(Ws& ws, Body&& body) {
  if (!ws.spring_block_f64.empty()) body(ws.spring_block_f64);
  else body(ws.spring_block_f32);
}

template <ImplicitLayout Layout, class Blocks>
inline Vec3 system_row(const Model& m, std::span<const Vec3> x, Real h, const Workspace& ws, const Blocks& blocks,
                       std::span<const Vec3> p, Index i) {
  Vec3 sum = apply_particle_block(m, i, 1 / m.particle_inv_mass[i], h, ws, p[i]);
  for (Index k = m.particle_spring_offset[i]; k < m.particle_spring_offset[i + 1]; ++k) {
    const Index e = m.particle_spring_index[k];
    const Index s = e >= 0 ? e : ~e;
    const Index j = e >= 0 ? m.spring_b[s] : m.spring_a[s];
    if constexpr (Layout == ImplicitLayout::spring_blocks) {
      sum += blocks[s] * (p[i] - p[j]);
    } else {
      const Index a = m.spring_a[s], b = m.spring_b[s];
      const SpringJacobian jac = spring_jacobian(x[a], x[b], m.spring_rest[s], m.spring_ke[s], m.spring_kd[s]);
      sum += spring_system_block(jac, h) * (p[i] - p[j]);
    }
  }
  return sum;
}

// The stitches' and hinges' part of row i of A p: their c c^T (x) (h Kv + h^2 Kx) blocks (systems/stitch_forces.h)
// and h^2 u u^T (systems/bend_forces.h). Apart from system_row so that the products of a model with neither test
// for them once, not in every row.
inline bool has_extra_terms(const Model& m) { return m.stitch_count > 0 || m.hinge_count > 0; }
// Adds them to sum, row i's other terms, in the order the row always summed them (the same bytes).
inline Vec3 add_extra_row(const Model& m, Real h, const Workspace& ws, std::span<const Vec3> p, Index i, Vec3 sum) {
  if (m.stitch_count > 0) sum += stitch_row(m, ws, i, p);
  if (m.hinge_count > 0) sum += (h * h) * hinge_row(m, ws.hinge_jac, i, p);
  return sum;
}

// Calls body(std::integral_constant<ImplicitLayout, layout>{}): the one dispatch from the run-time layout.
template <class Body>
inline void with_layout(ImplicitLayout layout, Body&& body) {
  if (layout == ImplicitLayout::spring_blocks) body(std::integral_constant<ImplicitLayout, ImplicitLayout::spring_blocks>{});
  else body(std::integral_constant<ImplicitLayout, ImplicitLayout::recompute>{});
}

// q = A p over all particles; pinned rows are zero.
inline void apply_system(const Model& m, std::span<const Vec3> x, Real h, ImplicitLayout layout, const Workspace& ws,
                         std::span<const Vec3> p, std::span<Vec3> q) {
  const bool extras = has_extra_terms(m);
  with_layout(layout, [&, extras](auto l) {
    with_spring_blocks(ws, [&, extras](const auto& blocks) {
      parallel_over(m.particle_count, particle_grain, [&, extras](Index i) {
        if (!(m.particle_inv_mass[i] > 0)) {
          q[i] = Vec3::Zero();
          return;
        }
        const Vec3 row = system_row<l()>(m, x, h, ws, blocks, p, i);
        q[i] = extras ? add_extra_row(m, h, ws, p, i, row) : row;
      });
    });
  });
}

}  // namespace clothsim
