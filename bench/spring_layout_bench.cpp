// Spring-force accumulation layouts side by side: per-particle gather (each spring computed from both
// ends) against two-phase (each spring once into a buffer, then a per-particle gather of the buffer).
// Both are deterministic (docs/performance.md, "Spring-force layouts"). Items are springs.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>

#include "core/build_model.h"
#include "core/csr.h"
#include "systems/spring_forces.h"

namespace {

using namespace clothsim;

BuiltScene deformed_grid(int n) {
  SceneDesc s;
  ClothDesc c;
  c.grid_nx = c.grid_ny = n;
  s.cloths.push_back(c);
  BuiltScene b = build_model(s, {make_cloth_grid(c)});
  build_particle_springs(b.model);  // the grid's default (blocked) layout goes without it
  for (std::size_t i = 0; i < b.state.x.size(); ++i) b.state.x[i].y() += 1e-3 * std::sin(0.1 * double(i));
  return b;
}

void run(benchmark::State& st, bool two_phase) {
  const int n = int(st.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, std::size_t(st.range(1)));
  const BuiltScene b = deformed_grid(n);
  std::vector<Vec3> f(b.model.particle_count), scratch(b.model.spring_count);
  // One untimed call first: the first touch of the fresh buffers (page faults) must not be timed.
  if (two_phase) eval_springs_two_phase(b.model, b.state.x, b.state.v, f, scratch);
  else eval_springs_gather(b.model, b.state.x, b.state.v, f);
  for (auto _ : st) {
    if (two_phase) eval_springs_two_phase(b.model, b.state.x, b.state.v, f, scratch);
    else eval_springs_gather(b.model, b.state.x, b.state.v, f);
    benchmark::DoNotOptimize(f.data());
  }
  st.SetItemsProcessed(st.iterations() * b.model.spring_count);
  st.counters["particles/s"] =
      benchmark::Counter(double(st.iterations()) * b.model.particle_count, benchmark::Counter::kIsRate);
}

void BM_springs_gather(benchmark::State& st) { run(st, false); }
void BM_springs_two_phase(benchmark::State& st) { run(st, true); }

}  // namespace

BENCHMARK(BM_springs_gather)->ArgsProduct({{256, 1024}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_springs_two_phase)->ArgsProduct({{256, 1024}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
