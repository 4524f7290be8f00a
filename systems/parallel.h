#pragma once
// The one way kernels go parallel: tbb::parallel_for over index blocks. Blocks are independent and every
// element is written by exactly one task, so results do not depend on the thread count.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/math.h"

namespace clothsim {

inline constexpr Index particle_grain = 2048;  // particles per task: a task's work outweighs its scheduling

template <class Body>
void parallel_over(Index n, Index grain, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, grain), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) body(i);
  });
}

}  // namespace clothsim
