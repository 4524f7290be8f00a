#pragma once
// Compressed sparse rows built by a counting sort, shared by every model builder.
#include <vector>

#include "core/math.h"

namespace clothsim {

// Groups (owner[k], entry[k]) pairs by owner into CSR: the entries of owner p are index[offset[p] ..
// offset[p + 1]). Entries of one owner keep their input order, so a gather that reads them sums in the same
// order at any thread count.
void build_csr(Index n, const std::vector<Index>& owner, const std::vector<Index>& entry,
               std::vector<Index>& offset, std::vector<Index>& index);

// The incident springs of every particle: entry = spring index, ~index (negative) when the particle is
// spring_b; fills model.particle_spring_offset / particle_spring_index.
struct Model;
void build_particle_springs(Model& model);

}  // namespace clothsim
