#include "core/spring_chunks.h"

#include <algorithm>
#include <bit>

namespace clothsim {

namespace {

Index auto_chunk_size(Index springs) {
  const Index want = std::max<Index>(1, springs / spring_chunks_wanted);
  return std::clamp(Index(std::bit_floor(std::uint64_t(want))), spring_chunk_min, spring_chunk_max);
}

// Appends to offset/range, per chunk, the runs of particles whose owner (opening or closing chunk) it is;
// owner == chunks (no span) goes to the last slot, handled after the passes.
void owner_ranges(const std::vector<Index>& owner, Index chunks, std::vector<Index>& offset,
                  std::vector<Index>& range) {
  std::vector<std::vector<Index>> per(chunks + 1);
  for (Index i = 0, n = Index(owner.size()); i < n;) {
    Index end = i + 1;
    while (end < n && owner[end] == owner[i]) ++end;
    per[owner[i]].insert(per[owner[i]].end(), {i, end});
    i = end;
  }
  offset.assign(1, 0);
  range.clear();
  for (const auto& r : per) {
    range.insert(range.end(), r.begin(), r.end());
    offset.push_back(Index(range.size() / 2));
  }
  // Held for the model's life: no spare capacity from the growth above (core/memory_bytes.h counts capacity).
  offset.shrink_to_fit();
  range.shrink_to_fit();
}

// spring_block_close: for each block of each chunk, how many of the chunk's closing particles (in the order of
// its close ranges) have no spring of the chunk after that block. A prefix, so the kernel closes by a cursor.
void build_block_close(Model& m, Index chunk_size, const std::vector<Index>& close) {
  std::vector<Index> last(m.particle_count, -1);  // last spring of its closing chunk touching the particle
  for (Index s = 0; s < m.spring_count; ++s)
    for (Index i : {m.spring_a[s], m.spring_b[s]})
      if (close[i] == s / chunk_size) last[i] = s;
  m.spring_block_close.assign((m.spring_count + spring_block_size - 1) / spring_block_size, 0);
  const Index chunks = Index(m.spring_chunk_offset.size()) - 1;
  for (Index c = 0; c < chunks; ++c) {
    Index r = m.spring_chunk_close_offset[c], r_end = m.spring_chunk_close_offset[c + 1];
    Index i = r < r_end ? m.spring_chunk_close_range[2 * r] : 0, done = 0, latest = -1;
    for (Index begin = m.spring_chunk_offset[c]; begin < m.spring_chunk_offset[c + 1]; begin += spring_block_size) {
      const Index block_end = std::min(begin + spring_block_size, m.spring_chunk_offset[c + 1]);
      while (r < r_end && std::max(latest, last[i]) < block_end) {
        latest = std::max(latest, last[i]);
        ++done;
        if (++i == m.spring_chunk_close_range[2 * r + 1] && ++r < r_end) i = m.spring_chunk_close_range[2 * r];
      }
      m.spring_block_close[begin / spring_block_size] = done;
    }
  }
}

}  // namespace

bool build_spring_chunks(Model& m, Index chunk_size, Index max_passes) {
  if (chunk_size <= 0) chunk_size = auto_chunk_size(m.spring_count);
  chunk_size = (chunk_size + spring_block_size - 1) / spring_block_size * spring_block_size;
  struct Span {
    Index lo, hi, chunk;
  };
  std::vector<std::vector<Span>> passes;
  std::vector<Index> offset{0};
  for (Index begin = 0; begin < m.spring_count; begin += chunk_size) {
    const Index end = std::min(begin + chunk_size, m.spring_count);
    Span span{m.spring_a[begin], m.spring_a[begin], Index(offset.size() - 1)};
    for (Index s = begin; s < end; ++s) {
      span.lo = std::min({span.lo, m.spring_a[s], m.spring_b[s]});
      span.hi = std::max({span.hi, m.spring_a[s], m.spring_b[s]});
    }
    offset.push_back(end);
    auto fits = [&](const std::vector<Span>& pass) {
      return std::none_of(pass.begin(), pass.end(), [&](const Span& o) { return o.lo <= span.hi && span.lo <= o.hi; });
    };
    auto pass = std::find_if(passes.begin(), passes.end(), fits);
    if (pass == passes.end()) {
      if (Index(passes.size()) == max_passes) return false;
      passes.emplace_back();
      pass = passes.end() - 1;
    }
    pass->push_back(span);
  }
  const Index chunks = Index(offset.size()) - 1;
  m.spring_chunk_offset = std::move(offset);
  m.spring_pass_offset.assign(1, 0);
  m.spring_pass_chunk.clear();
  // Opening chunk: the first in pass order whose span holds the particle; closing chunk: the last.
  std::vector<Index> open(m.particle_count, chunks), close(m.particle_count, chunks);
  for (const auto& pass : passes) {
    for (const Span& s : pass) {
      m.spring_pass_chunk.push_back(s.chunk);
      for (Index i = s.lo; i <= s.hi; ++i) {
        if (open[i] == chunks) open[i] = s.chunk;
        close[i] = s.chunk;
      }
    }
    m.spring_pass_offset.push_back(Index(m.spring_pass_chunk.size()));
  }
  owner_ranges(open, chunks, m.spring_chunk_open_offset, m.spring_chunk_open_range);
  owner_ranges(close, chunks, m.spring_chunk_close_offset, m.spring_chunk_close_range);
  build_block_close(m, chunk_size, close);
  return true;
}

}  // namespace clothsim
