#include "core/spring_chunks.h"

#include <algorithm>

namespace clothsim {

bool build_spring_chunks(Model& m, Index chunk_size, Index max_passes) {
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
  m.spring_chunk_offset = std::move(offset);
  m.spring_pass_offset.assign(1, 0);
  m.spring_pass_chunk.clear();
  for (const auto& pass : passes) {
    for (const Span& s : pass) m.spring_pass_chunk.push_back(s.chunk);
    m.spring_pass_offset.push_back(Index(m.spring_pass_chunk.size()));
  }
  return true;
}

}  // namespace clothsim
