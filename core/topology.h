#pragma once
// Mesh topology in linear time: unique edges through an open-addressing hash map of vertex pairs, the bend
// pair across each interior edge, and the counts `clothsim info` reports.
#include <vector>

#include "core/mesh_data.h"

namespace clothsim {

struct Topology {
  std::vector<Index> edge_a, edge_b;  // unique edges, a < b, in order of first appearance (edge_count)
  std::vector<Index> bend_a, bend_b;  // vertices opposite each edge shared by exactly two triangles
  std::vector<Index> bend_edge;       // the edge each bend pair straddles, into edge_a/edge_b (bend_count)
  Index boundary_edges = 0;           // edges of one triangle
  Index nonmanifold_edges = 0;        // edges of three or more triangles: no bend spring
  Index degenerate_triangles = 0;     // repeated corner or zero area
  Index pieces = 0;                   // connected components over the triangles (unused vertices excluded)
  Index unused_vertices = 0;          // vertices no triangle references

  Index edge_count() const { return static_cast<Index>(edge_a.size()); }
  Index bend_count() const { return static_cast<Index>(bend_a.size()); }
};

Topology build_topology(const MeshData& mesh);

// Twice the area of triangle t (the length of its edge cross product), m^2.
Real twice_triangle_area(const MeshData& mesh, Index t);

}  // namespace clothsim
