// The two roofs of docs/performance.md ("Roofline"), measured in the same binary as the kernels:
//  - memory: a STREAM triad a = b + s c over arrays far larger than the caches, at 1 thread and every core;
//  - arithmetic: the spring's own operations (bench/spring_ops.h), scalar and vectorised.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <cmath>
#include <vector>

#include "bench/spring_ops.h"

namespace {

using namespace clothsim::bench;

constexpr std::size_t triad_elements = std::size_t(1) << 24;  // 3 arrays x 128 MB, beyond any L3 here

void BM_triad(benchmark::State& st) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, st.range(0));
  static std::vector<double> a(triad_elements, 0.0), b(triad_elements, 1.0), c(triad_elements, 2.0);
  const double s = 3.0;
  tbb::static_partitioner part;  // each thread keeps its own pages from one batch to the next
  for (auto _ : st) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triad_elements, 1 << 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i) a[i] = b[i] + s * c[i];
                      },
                      part);
    benchmark::ClobberMemory();
  }
  // STREAM counts 24 bytes per element (two reads, one write), not the write-allocate read.
  st.SetBytesProcessed(int64_t(st.iterations()) * int64_t(triad_elements * 3 * sizeof(double)));
}

template <bool vectorise>
void BM_spring_ops(benchmark::State& st) {
  SpringSoA s;
  for (auto _ : st) {
    if constexpr (vectorise) eval_spring_ops(s, 1000.0, 0.1);
    else eval_spring_ops_scalar(s, 1000.0, 0.1);
    benchmark::DoNotOptimize(s.fx.data());
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(int64_t(st.iterations()) * SpringSoA::n);
}

void thread_counts(benchmark::internal::Benchmark* b) {
  b->Arg(1);
  if (tbb::info::default_concurrency() > 1) b->Arg(tbb::info::default_concurrency());
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_triad)->Apply(thread_counts);
BENCHMARK_TEMPLATE(BM_spring_ops, false)->Name("BM_spring_ops/scalar");
BENCHMARK_TEMPLATE(BM_spring_ops, true)->Name("BM_spring_ops/simd");

}  // namespace
