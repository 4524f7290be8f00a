#pragma once
// The particle graph of the implicit step's matrix (core/cholesky_factor.h): which particles the matrix couples,
// the fill-reducing orderings of that graph, and its connected pieces.
#include <vector>

#include <Eigen/SparseCore>

#include "core/math.h"

namespace clothsim {

struct Model;

using ParticleGraph = Eigen::SparseMatrix<Real, Eigen::ColMajor, int>;

// Fill-reducing orderings of the particle graph: the cheaper of the two that follow, nested dissection (METIS
// through CHOLMOD, approximate minimum degree where CHOLMOD has no METIS), or approximate minimum degree (Eigen's).
enum class CholeskyOrdering { cheaper, nested_dissection, minimum_degree };

// The particles and the pairs the matrix couples (the ends of every spring, each two distinct particles of a
// stitch, each two of a dihedral hinge's four), as a symmetric pattern (both triangles, compressed).
ParticleGraph particle_graph(const Model& m);

// The orderings to analyse for the one asked, each as vertex -> its place: nested dissection then minimum degree
// for the cheaper of the two; nested dissection falls back to minimum degree where CHOLMOD has no METIS.
std::vector<std::vector<int>> candidate_orderings(ParticleGraph& graph, CholeskyOrdering ordering);

// The connected pieces of the graph, grouped: particle -> its group. A piece of piece_group_particles or more is a
// group of its own; smaller ones, taken in the order of their first particle, are gathered into a group until it
// holds that many, so a mesh of many small pieces does not make as many factors. group_count: the groups made.
inline constexpr Index piece_group_particles = 512;
std::vector<int> piece_groups(const ParticleGraph& graph, int& group_count);

// The graph of the given particles (ascending), numbered by their rank.
ParticleGraph subgraph(const ParticleGraph& graph, const std::vector<Index>& members, const std::vector<int>& rank);

}  // namespace clothsim
