#pragma once
// Sums and other reductions over particles that give the same bytes at any thread count:
// tbb::parallel_deterministic_reduce splits the range into the same fixed blocks every time and joins them in the
// same order.
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "core/math.h"

namespace clothsim {

// Sum of term(i) over [0, n), where term returns Real or a fixed-size Eigen vector (several sums in one pass).
template <class T, class Term>
T deterministic_sum(Index n, Index grain, const T& zero, Term&& term) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<Index>(0, n, grain), zero,
      [&](const tbb::blocked_range<Index>& r, T sum) {
        for (Index i = r.begin(); i != r.end(); ++i) sum += term(i);
        return sum;
      },
      [](const T& a, const T& b) -> T { return a + b; });
}

// join(... join(init, f(0)) ..., f(n - 1)) over [0, n), blocks joined in the same order at any thread count: for
// minima, counts and other reductions whose join is not a plain sum.
template <class T, class PerIndex, class Join>
T deterministic_reduce(Index n, Index grain, const T& init, PerIndex&& f, Join&& join) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<Index>(0, n, grain), init,
      [&](const tbb::blocked_range<Index>& r, T acc) {
        for (Index i = r.begin(); i != r.end(); ++i) acc = join(acc, f(i));
        return acc;
      },
      join);
}

}  // namespace clothsim
