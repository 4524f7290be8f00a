#pragma once
// Per-vertex parameters sampled from a cloth's maps (io/cloth_maps), handed to model building as plain
// arrays so core needs no image code. An empty array means "the cloth's uniform value from ClothDesc".
#include <vector>

#include "core/math.h"

namespace clothsim {

struct VertexParams {
  std::vector<Real> density;    // kg/m^2, lumped to the vertices by area (vertex_count or 0)
  std::vector<Real> mass;       // kg per vertex (vertex_count or 0)
  std::vector<Real> stiffness;  // N/m; a spring takes the mean of its two ends (vertex_count or 0)
  std::vector<Real> damping;    // N s/m; a spring takes the mean of its two ends (vertex_count or 0)
  std::vector<Real> thickness;  // m (vertex_count or 0)
  std::vector<char> pinned;     // 1 where the pins map is above half grey (vertex_count or 0)
  // per <attach> of the cloth: 1 where its map is above half grey (vertex_count, or 0 for a vertex list)
  std::vector<std::vector<char>> attached;
};

}  // namespace clothsim
