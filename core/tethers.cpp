#include "core/tethers.h"

#include <cmath>
#include <limits>
#include <queue>
#include <utility>

#include "core/csr.h"

namespace clothsim {

void build_tethers(Model& m, std::span<const Vec3> rest, std::span<const char> straight_rest) {
  m.tether_particle.clear();
  m.tether_pin.clear();
  m.tether_length.clear();
  // Each limited cloth's maxStrain (every spring of a cloth has its cloth's value), +inf for the others.
  const Real inf = std::numeric_limits<Real>::infinity();
  std::vector<Real> cloth_strain(m.cloths.size(), inf);
  std::vector<Index> particle_cloth(m.particle_count, -1);
  for (std::size_t c = 0; c < m.cloths.size(); ++c) {
    const ClothInfo& info = m.cloths[c];
    if (info.spring_begin < info.spring_end) cloth_strain[c] = m.spring_max_strain[info.spring_begin];
    for (Index i = info.particle_begin; i < info.particle_end; ++i) particle_cloth[i] = Index(c);
  }
  // Dijkstra from every pin of a limited cloth at once: each particle settles at its nearest pin. The queue
  // orders by (distance, particle), so the search and its ties are the same every run.
  std::vector<Real> dist(m.particle_count, inf);
  std::vector<Index> pin(m.particle_count, -1);
  using Entry = std::pair<Real, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (Index p : m.pinned) {
    const Index c = particle_cloth[p];
    if (c < 0 || !std::isfinite(cloth_strain[c])) continue;
    dist[p] = 0;
    pin[p] = p;
    queue.push({0, p});
  }
  if (queue.empty()) return;
  // The spring CSR, borrowed from the model where a kernel already keeps it, else built for this search only.
  std::vector<Index> own_offset, own_index;
  if (m.particle_spring_offset.empty()) build_particle_springs(m, own_offset, own_index);
  const std::vector<Index>& offset = m.particle_spring_offset.empty() ? own_offset : m.particle_spring_offset;
  const std::vector<Index>& index = m.particle_spring_offset.empty() ? own_index : m.particle_spring_index;
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    for (Index k = offset[i]; k < offset[i + 1]; ++k) {
      const Index e = index[k], s = e >= 0 ? e : ~e;
      const Index j = e >= 0 ? m.spring_b[s] : m.spring_a[s];
      const Real next = d + m.spring_rest[s];
      if (next < dist[j]) {
        dist[j] = next;
        pin[j] = pin[i];
        queue.push({next, j});
      }
    }
  }
  for (Index i = 0; i < m.particle_count; ++i) {
    if (pin[i] < 0 || !(m.particle_inv_mass[i] > 0)) continue;
    const Index c = particle_cloth[i];
    const Real rest_distance = straight_rest[c] ? (rest[i] - rest[pin[i]]).norm() : dist[i];
    m.tether_particle.push_back(i);
    m.tether_pin.push_back(pin[i]);
    m.tether_length.push_back((1 + cloth_strain[c]) * rest_distance);
  }
  // Held for the model's life: no spare capacity from the growth above (core/memory_bytes.h counts capacity).
  m.tether_particle.shrink_to_fit();
  m.tether_pin.shrink_to_fit();
  m.tether_length.shrink_to_fit();
}

}  // namespace clothsim
