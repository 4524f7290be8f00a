#include "systems/multigrid.h"

#include <type_traits>

#include "systems/parallel.h"

namespace clothsim {
namespace {

// The cycle's constants: those that took the fewest instructions on the peer sheet (docs/performance.md, "The
// multigrid preconditioner", gives the sweep over omega and alpha and the V-cycle against the W-cycle).
constexpr Real omega = 0.6;  // damping of the block-Jacobi sweep, in (0, 1) (the contraction argument, multigrid.h)
constexpr int gamma = 2;     // coarse cycles per visit of a level not solved exactly: the W-cycle
constexpr Real alpha = 1.3;  // scale of the coarse correction, in (0, 2) (multigrid.h)

// Levels below the particle grain are one block anyway: run them inline, without a task per pass.
template <class Body>
void for_nodes(Index n, Body&& body) {
  if (n <= particle_grain) {
    for (Index i = 0; i < n; ++i) body(i);
  } else {
    parallel_over(n, particle_grain, body);
  }
}

// The finest level: the particles, their rows of the CG's own matrix (pinned rows zero), block-Jacobi inverses.
template <ImplicitLayout Layout, class Blocks>
struct FineLevel {
  const Model& m;
  std::span<const Vec3> x;
  Real h;
  const Workspace& ws;
  const Blocks& blocks;
  Index size() const { return m.particle_count; }
  bool active(Index i) const { return m.particle_inv_mass[i] > 0; }
  bool extras = has_extra_terms(m);
  Vec3 row(std::span<const Vec3> p, Index i) const {
    const Vec3 r = system_row<Layout>(m, x, h, ws, blocks, p, i);
    return extras ? add_extra_row(m, h, ws, p, i, r) : r;
  }
  const Sym3& diag_inv(Index i) const { return ws.cg_precond[i]; }
};

// A coarse level: (A_c p)_I = D_I p_I - sum over its row entries of B p_J.
struct CoarseLevel {
  const MultigridLevel& L;
  Index size() const { return L.node_count; }
  bool active(Index) const { return true; }
  Vec3 row(std::span<const Vec3> p, Index n) const {
    Vec3 sum = L.diag[n] * p[n];
    for (Index k = L.row_offset[n]; k < L.row_offset[n + 1]; ++k) sum -= L.edge_block[L.row_edge[k]] * p[L.row_col[k]];
    return sum;
  }
  const Sym3& diag_inv(Index n) const { return L.diag_inv[n]; }
};

template <class Fine>
struct Cycle {
  const Fine fine;
  Multigrid& mg;

  Index coarsest() const { return Index(mg.levels.size()); }

  // out ~ A_l^-1 b by one cycle, from out = 0 (zero_start) or from the out given; s is scratch of the level's size.
  void run(Index l, std::span<const Vec3> b, std::span<Vec3> out, std::span<Vec3> s, bool zero_start) {
    if (l == 0) return run_on(fine, l, b, out, s, zero_start);
    if (l == coarsest() && mg.dense_coarsest) return solve_dense(b, out);
    run_on(CoarseLevel{mg.levels[l - 1]}, l, b, out, s, zero_start);
  }

  template <class Level>
  void run_on(const Level& lv, Index l, std::span<const Vec3> b, std::span<Vec3> out, std::span<Vec3> s,
              bool zero_start) {
    // Pre-smoothing, one damped block-Jacobi sweep into s: from zero it needs no product.
    for_nodes(lv.size(), [&](Index n) {
      if (!lv.active(n)) s[n] = Vec3::Zero();
      else if (zero_start) s[n] = omega * (lv.diag_inv(n) * b[n]);
      else s[n] = out[n] + omega * (lv.diag_inv(n) * (b[n] - lv.row(out, n)));
    });
    if (l < coarsest()) {
      MultigridLevel& C = mg.levels[l];
      // Restriction of the residual, P^T (b - A s): each aggregate sums its members' rows (each row once).
      for_nodes(C.node_count, [&](Index n) {
        Vec3 sum = Vec3::Zero();
        for (Index k = C.member_offset[n]; k < C.member_offset[n + 1]; ++k) {
          const Index i = C.member_index[k];
          sum += b[i] - lv.row(s, i);
        }
        C.b[n] = sum;
      });
      // W-cycle: the coarse problem gets two cycles (the second from the first's result), except where it is
      // solved exactly.
      const bool exact = l + 1 == coarsest() && mg.dense_coarsest;
      for (int g = 0; g < (exact ? 1 : gamma); ++g) run(l + 1, C.b, C.x, C.t, g == 0);
      // Prolongation: each member takes its aggregate's correction, scaled.
      for_nodes(lv.size(), [&](Index i) {
        if (C.parent[i] >= 0) s[i] += alpha * C.x[C.parent[i]];
      });
    }
    // Post-smoothing, the same sweep, into out.
    for_nodes(lv.size(), [&](Index n) {
      out[n] = lv.active(n) ? Vec3(s[n] + omega * (lv.diag_inv(n) * (b[n] - lv.row(s, n)))) : Vec3(Vec3::Zero());
    });
  }

  void solve_dense(std::span<const Vec3> b, std::span<Vec3> out) {
    const Index n = mg.levels.back().node_count;
    for (Index k = 0; k < n; ++k) mg.dense_rhs.segment<3>(3 * k) = b[k];
    const auto lower = mg.dense_factor.triangularView<Eigen::Lower>();
    lower.solveInPlace(mg.dense_rhs);
    lower.adjoint().solveInPlace(mg.dense_rhs);
    for (Index k = 0; k < n; ++k) out[k] = mg.dense_rhs.segment<3>(3 * k);
  }
};

// Sum of blocks[index[k]] over k in [offset[n], offset[n + 1]), in double.
template <class Block>
Sym3 sum_blocks(const std::vector<Index>& offset, const std::vector<Index>& index, const std::vector<Block>& blocks,
                Index n) {
  Sym3 sum;
  for (Index k = offset[n]; k < offset[n + 1]; ++k) sum += blocks[index[k]];
  return sum;
}

}  // namespace

void build_multigrid_operators(const Model& m, Real h, Workspace& ws) {
  Multigrid& mg = ws.multigrid;
  // Each level's G, into its diag: a coarser level's G sums the finer level's, so every G is formed before any
  // diag is finished below (the same sums in the same order as with an array of G apart).
  for (std::size_t l = 0; l < mg.levels.size(); ++l) {
    MultigridLevel& L = mg.levels[l];
    for_nodes(L.node_count, [&](Index n) {
      if (l == 0) {
        // An aggregate of particles: their blocks outside the springs, and their springs to pinned particles.
        Mat3 g = Mat3::Zero();
        for (Index k = L.member_offset[n]; k < L.member_offset[n + 1]; ++k) {
          const Index i = L.member_index[k];
          g += particle_system_block(m, i, 1 / m.particle_inv_mass[i], h, ws);
          // Stitches join panels that no aggregate spans; their diagonal, kept here, stops the coarse levels from
          // taking a sewn panel as free to move (systems/stitch_forces.h).
          if (m.stitch_count > 0) g += stitch_diagonal(m, ws, i).full();
        }
        L.diag[n] = Sym3::from(g);
        with_spring_blocks(ws, [&](const auto& b) { L.diag[n] += sum_blocks(L.ground_offset, L.ground_index, b, n); });
      } else {
        L.diag[n] = sum_blocks(L.member_offset, L.member_index, mg.levels[l - 1].diag, n);
      }
    });
  }
  for (std::size_t l = 0; l < mg.levels.size(); ++l) {
    MultigridLevel& L = mg.levels[l];
    // The finer level's edge blocks: the springs' on the first level.
    const auto sum_edges = [&](const auto& finer_edges) {
      for_nodes(L.edge_count, [&](Index e) {
        L.edge_block[e] = Sym3f::cast(sum_blocks(L.source_offset, L.source_index, finer_edges, e));
      });
    };
    if (l == 0) with_spring_blocks(ws, sum_edges);
    else sum_edges(mg.levels[l - 1].edge_block);
    for_nodes(L.node_count, [&](Index n) {
      Sym3 d = L.diag[n];
      for (Index k = L.row_offset[n]; k < L.row_offset[n + 1]; ++k) d += L.edge_block[L.row_edge[k]];
      L.diag[n] = d;
      L.diag_inv[n] = Sym3::from(d.full().inverse());
    });
  }
  if (mg.dense_coarsest) {
    const MultigridLevel& L = mg.levels.back();
    mg.dense.setZero();
    for (Index n = 0; n < L.node_count; ++n) {
      mg.dense.block<3, 3>(3 * n, 3 * n) = L.diag[n].full();
      for (Index k = L.row_offset[n]; k < L.row_offset[n + 1]; ++k)
        mg.dense.block<3, 3>(3 * n, 3 * L.row_col[k]) = -L.edge_block[L.row_edge[k]].full();
    }
    mg.dense_factor = mg.dense;  // same size: no allocation
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> in_place(mg.dense_factor);
  }
}

void apply_multigrid(const Model& m, std::span<const Vec3> x, Real h, ImplicitLayout layout, Workspace& ws,
                     std::span<const Vec3> r, std::span<Vec3> z) {
  with_layout(layout, [&](auto l) {
    with_spring_blocks(ws, [&](const auto& blocks) {
      Cycle<FineLevel<l(), std::decay_t<decltype(blocks)>>> cycle{{m, x, h, ws, blocks}, ws.multigrid};
      cycle.run(0, r, z, ws.f, true);
    });
  });
}

}  // namespace clothsim
