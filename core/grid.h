#pragma once
// The procedural grid cloth: an NX x NY sheet in the XZ plane centred at the origin, vertex (i, j) at index
// j*NX + i, UVs over 0..1, with Provot's (1995) structural, shear and flex springs.
#include <vector>

#include "core/mesh_data.h"
#include "core/model.h"

namespace clothsim {

struct SpringList {
  std::vector<Index> a, b;
  std::vector<SpringKind> kind;
  void add(Index i, Index j, SpringKind k) { a.push_back(i); b.push_back(j); kind.push_back(k); }
  Index size() const { return static_cast<Index>(a.size()); }
};

MeshData make_grid_mesh(int nx, int ny, Real width, Real height);
SpringList make_grid_springs(int nx, int ny);

}  // namespace clothsim
