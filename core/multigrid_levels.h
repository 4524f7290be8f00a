#pragma once
// The levels of the implicit step's multigrid preconditioner (systems/multigrid.h): aggregates of particles
// formed by pairwise matching, twice per level (Notay 2010, "An aggregation-based algebraic multigrid method",
// ETNA 37: pairwise aggregation), from the springs and their stiffness when the workspace is made, so a level's
// topology is fixed for the run and only its numeric blocks are recomputed each step.
//
// The prolongation is piecewise constant, one 3x3 identity per aggregate (plain, unsmoothed aggregation). Then the
// Galerkin operator P^T A P keeps the form of the fine one, A p = G p + sum over edges of B_e (p_a - p_b): each
// aggregate's G is the sum of its members' G (and, on the first level, of its springs to pinned particles, whose
// columns the filter removes), each coarse edge's B the sum of the finer edges that join the two aggregates, and
// edges inside an aggregate drop out. So every level applies its operator with the same gather per node.
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "core/math.h"

namespace clothsim {

struct Model;

// One coarse level. Its nodes are aggregates of the finer level's nodes: free particles for the first level
// (pinned particles belong to none), the previous level's nodes after that. Its edges are the pairs of aggregates
// that finer edges join; the first level's finer edges are the springs.
struct MultigridLevel {
  Index node_count = 0;
  Index edge_count = 0;
  std::vector<Index> parent;         // aggregate of each finer node, -1 for a pinned particle (finer node count)
  std::vector<Index> member_offset;  // finer nodes of each aggregate, in index order (node_count + 1)
  std::vector<Index> member_index;   // (finer nodes with a parent)
  // The operator's rows: for each node, its neighbours across its edges and those edges, in edge order
  // (row_offset: node_count + 1; row_col, row_edge: 2 * edge_count). An edge joins two distinct aggregates, each
  // pair once, and is numbered by (lower aggregate, higher aggregate); the rows are all that stores its ends.
  std::vector<Index> row_offset, row_col, row_edge;
  std::vector<Index> source_offset;     // finer edges summed into each edge, in index order (edge_count + 1)
  std::vector<Index> source_index;      // (finer edges joining two aggregates)
  // first level only: springs from an aggregate's particles to pinned particles, which the filter turns into
  // diagonal terms (node_count + 1, or empty on later levels)
  std::vector<Index> ground_offset, ground_index;

  // Numeric blocks, recomputed each step (systems/multigrid.cpp).
  std::vector<Sym3f> edge_block;  // B of each edge, float as the springs' (edge_count)
  // The node's diagonal block, G + the sum of its edges' B (node_count). While the step's blocks are built it
  // holds G, the node's block outside its edges, which the next level's G sums: no array of its own for G.
  std::vector<Sym3> diag;
  std::vector<Sym3> diag_inv;    // its inverse (node_count)
  std::vector<Vec3> b, x, t;     // the cycle's right-hand side, result and scratch on this level (node_count)
};

struct Multigrid {
  std::vector<MultigridLevel> levels;  // levels[0] aggregates the particles; each later one the level before
  // The coarsest level is solved by a dense Cholesky factorisation when it is small enough (dense_max_nodes);
  // otherwise (coarsening stalled on many disconnected pieces) it is only smoothed.
  bool dense_coarsest = false;
  Eigen::MatrixXd dense;              // (3 n x 3 n) of the coarsest level, assembled each step
  // Its Cholesky factor L in the lower triangle, factored in place each step. Not an Eigen::LLT member: an LLT
  // leaves its status field unset until compute(), so moving the model-time Multigrid would copy an unset enum
  // (undefined behaviour).
  Eigen::MatrixXd dense_factor;
  Eigen::VectorXd dense_rhs;          // (3 n)
};

// Levels are added until one has at most coarsest_nodes nodes, or an added level would keep more than
// stall_ratio of the previous one's nodes (disconnected pieces each end as one node). At least one level is
// built where the springs allow any aggregation.
inline constexpr Index multigrid_coarsest_nodes = 64;
inline constexpr Index multigrid_dense_max_nodes = 256;
Multigrid build_multigrid_levels(const Model& model, Index coarsest_nodes = multigrid_coarsest_nodes);

}  // namespace clothsim
