#include "core/csr.h"

#include <numeric>

#include "core/model.h"

namespace clothsim {
namespace {

// Counting sort over an implicit list of (owner, entry) pairs that `visit(emit)` produces, twice: once to
// count, once to fill. Entries of one owner keep the visit order.
template <class Visit>
void counting_csr(Index n, std::size_t entries, Visit visit, std::vector<Index>& offset, std::vector<Index>& index) {
  offset.assign(std::size_t(n) + 1, 0);
  visit([&](Index owner, Index) { ++offset[owner + 1]; });
  std::partial_sum(offset.begin(), offset.end(), offset.begin());
  index.resize(entries);
  // The fill cursor of each owner is offset[owner], advanced in place, then shifted back by one owner.
  visit([&](Index owner, Index entry) { index[offset[owner]++] = entry; });
  for (Index p = n; p > 0; --p) offset[p] = offset[p - 1];
  offset[0] = 0;
}

}  // namespace

void build_particle_springs(const Model& m, std::vector<Index>& offset, std::vector<Index>& index) {
  counting_csr(m.particle_count, 2 * std::size_t(m.spring_count),
               [&](auto emit) {
                 for (Index s = 0; s < m.spring_count; ++s) {
                   emit(m.spring_a[s], s);
                   emit(m.spring_b[s], ~s);
                 }
               },
               offset, index);
}

void build_particle_springs(Model& m) { build_particle_springs(m, m.particle_spring_offset, m.particle_spring_index); }

void build_particle_hinges(Model& m) {
  counting_csr(m.particle_count, 4 * std::size_t(m.hinge_count),
               [&](auto emit) {
                 for (Index h = 0; h < m.hinge_count; ++h) {
                   emit(m.hinge_o1[h], 4 * h);
                   emit(m.hinge_o2[h], 4 * h + 1);
                   emit(m.hinge_e0[h], 4 * h + 2);
                   emit(m.hinge_e1[h], 4 * h + 3);
                 }
               },
               m.particle_hinge_offset, m.particle_hinge_index);
}

bool needs_particle_springs(const Model& m, Integrator integrator) {
  return m.spring_layout != SpringLayout::blocked || integrator == Integrator::implicit;
}

void ensure_particle_springs(Model& m, Integrator integrator) {
  if (needs_particle_springs(m, integrator) && m.particle_spring_offset.empty()) build_particle_springs(m);
}

void build_particle_tris(Model& m) {
  counting_csr(m.particle_count, m.tri_index.size(),
               [&](auto emit) {
                 for (std::size_t k = 0; k < m.tri_index.size(); ++k) emit(m.tri_index[k], Index(k / 3));
               },
               m.particle_tri_offset, m.particle_tri_index);
}

}  // namespace clothsim
