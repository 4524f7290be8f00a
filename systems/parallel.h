#pragma once
// The one way kernels go parallel: tbb::parallel_for over index blocks. Blocks are independent and every
// element is written by exactly one task, so results do not depend on the thread count.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>

#include "core/math.h"

namespace clothsim {

inline constexpr Index particle_grain = 2048;  // particles per task: a task's work outweighs its scheduling

template <class Body>
void parallel_over(Index n, Index grain, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, grain), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) body(i);
  });
}

// Jobs of very unequal length (the Cholesky factor's pieces): each free thread takes the next job in index order,
// so jobs listed longest first make a greedy list schedule (Graham 1969), within 4/3 of the best. Each job runs
// on one thread, so results do not depend on the thread count as long as the jobs are independent.
template <class Body>
void parallel_hand_out(Index n, Body&& body) {
  if (n <= 1) {
    if (n == 1) body(Index(0));
    return;
  }
  std::atomic<Index> next{0};
  const int takers = std::min(int(n), tbb::this_task_arena::max_concurrency());
  tbb::parallel_for(0, takers, [&](int) {
    for (Index k = next++; k < n; k = next++) body(k);
  });
}

}  // namespace clothsim
