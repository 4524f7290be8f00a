#include "core/spring_colours.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace clothsim {

bool spring_is_limited(const Model& m, Index s) {
  return std::isfinite(m.spring_max_strain[s]) &&
         (m.particle_inv_mass[m.spring_a[s]] > 0 || m.particle_inv_mass[m.spring_b[s]] > 0);
}

void build_spring_colours(Model& m) {
  // A bit mask of the colours already at each particle, 64 colours a round; springs left over when a particle
  // has all 64 of a round's colours (degree above 32) go to the next round.
  constexpr Index round_colours = 64;
  std::vector<Index> colour(m.spring_count, -1);
  std::vector<std::uint64_t> used(m.particle_count);
  Index rounds = 0;
  for (bool left = true; left; ++rounds) {
    left = false;
    std::fill(used.begin(), used.end(), 0);
    for (Index s = 0; s < m.spring_count; ++s) {
      if (colour[s] >= 0 || !spring_is_limited(m, s)) continue;
      const Index a = m.spring_a[s], b = m.spring_b[s];
      const std::uint64_t free = ~(used[a] | used[b]);
      if (free == 0) {
        left = true;
        continue;
      }
      const int c = std::countr_zero(free);
      colour[s] = rounds * round_colours + c;
      used[a] |= std::uint64_t(1) << c;
      used[b] |= std::uint64_t(1) << c;
    }
  }
  // Counting sort by colour; colours no spring took (a round that used fewer than 64) are dropped.
  std::vector<Index> count(std::size_t(rounds) * round_colours, 0);
  for (Index c : colour)
    if (c >= 0) ++count[c];
  std::vector<Index> start(count.size(), 0);
  m.spring_colour_offset.assign(1, 0);
  for (std::size_t c = 0; c < count.size(); ++c) {
    start[c] = m.spring_colour_offset.back();
    if (count[c] > 0) m.spring_colour_offset.push_back(start[c] + count[c]);
  }
  m.spring_colour_offset.shrink_to_fit();
  m.spring_colour_spring.assign(m.spring_colour_offset.back(), 0);
  for (Index s = 0; s < m.spring_count; ++s)
    if (colour[s] >= 0) m.spring_colour_spring[start[colour[s]]++] = s;
  // Each particle's entries, by a counting sort of the entries' two ends.
  m.particle_colour_offset.assign(std::size_t(m.particle_count) + 1, 0);
  for (Index s : m.spring_colour_spring) {
    ++m.particle_colour_offset[std::size_t(m.spring_a[s]) + 1];
    ++m.particle_colour_offset[std::size_t(m.spring_b[s]) + 1];
  }
  std::partial_sum(m.particle_colour_offset.begin(), m.particle_colour_offset.end(), m.particle_colour_offset.begin());
  m.particle_colour_entry.assign(std::size_t(m.particle_colour_offset.back()), 0);
  std::vector<Index> next(m.particle_colour_offset.begin(), m.particle_colour_offset.end() - 1);
  for (Index k = 0; k < Index(m.spring_colour_spring.size()); ++k) {
    const Index s = m.spring_colour_spring[k];
    m.particle_colour_entry[next[m.spring_a[s]]++] = k;
    m.particle_colour_entry[next[m.spring_b[s]]++] = k;
  }
}

}  // namespace clothsim
