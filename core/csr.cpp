#include "core/csr.h"

#include <numeric>

#include "core/model.h"

namespace clothsim {

void build_csr(Index n, const std::vector<Index>& owner, const std::vector<Index>& entry,
               std::vector<Index>& offset, std::vector<Index>& index) {
  offset.assign(std::size_t(n) + 1, 0);
  for (Index p : owner) ++offset[p + 1];
  std::partial_sum(offset.begin(), offset.end(), offset.begin());
  index.resize(owner.size());
  std::vector<Index> fill(offset.begin(), offset.end() - 1);
  for (std::size_t k = 0; k < owner.size(); ++k) index[fill[owner[k]]++] = entry[k];
}

void build_particle_springs(Model& m) {
  std::vector<Index> owner, entry;
  owner.reserve(2 * std::size_t(m.spring_count));
  entry.reserve(2 * std::size_t(m.spring_count));
  for (Index s = 0; s < m.spring_count; ++s) {
    owner.push_back(m.spring_a[s]); entry.push_back(s);
    owner.push_back(m.spring_b[s]); entry.push_back(~s);
  }
  build_csr(m.particle_count, owner, entry, m.particle_spring_offset, m.particle_spring_index);
}

}  // namespace clothsim
