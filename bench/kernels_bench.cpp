// Per-kernel benchmarks on 64^2, 256^2 and 1024^2 sheets (docs/performance.md), in the style of MuJoCo's step
// benchmark: build once, warm up, save the state, restore it before each timed batch. Second argument: threads.
// Counters: items_per_second (springs/s or particle-steps/s) and bytes_per_second (kernel_traffic.h's model).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <map>
#include <memory>

#include "bench/kernel_traffic.h"
#include "core/csr.h"
#include "core/spring_chunks.h"
#include "io/obj_writer.h"
#include "systems/normals.h"
#include "systems/spring_forces.h"
#include "systems/step.h"
#include "tests/support/sheet_scene.h"

namespace clothsim::bench {
namespace {

struct Fixture {
  BuiltScene built;
  Workspace ws;
  State warm;  // the state after warm-up, restored before each batch
};

// One fixture per (size, integrator), built on first use: the 1024^2 sheet takes seconds to build.
Fixture& fixture(int n, Integrator integ) {
  static std::map<std::pair<int, int>, std::unique_ptr<Fixture>> cache;
  auto& slot = cache[{n, int(integ)}];
  if (!slot) {
    slot = std::make_unique<Fixture>();
    slot->built = build_sheet(n, integ);
    build_particle_springs(slot->built.model);  // the gather and two_phase cases run on this blocked model too
    slot->ws = make_workspace(slot->built.model, slot->built.options);
    State scratch = slot->built.state;
    // Warm-up: a few steps so the sheet is strained and moving, not at rest (rest springs are cheaper for none
    // of the kernels, but a moving state is the honest one).
    for (int k = 0; k < 5; ++k) {
      step(slot->built.model, slot->built.options, slot->built.state, scratch, slot->ws, slot->built.options.dt);
      std::swap(slot->built.state, scratch);
    }
    slot->warm = slot->built.state;
  }
  return *slot;
}

void set_counters(benchmark::State& st, double items, double bytes) {
  st.SetItemsProcessed(int64_t(items * double(st.iterations())));
  st.SetBytesProcessed(int64_t(bytes * double(st.iterations())));
}

void BM_springs(benchmark::State& st, BenchLayout layout) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, st.range(1));
  Fixture& fx = fixture(int(st.range(0)), Integrator::symplectic);
  const Model& m = fx.built.model;
  const State& s = fx.warm;
  std::vector<Vec3> scratch(m.spring_count);  // two_phase's buffer, owned here so every layout runs on one model
  auto run = [&] { eval_springs_as(layout, m, s.x, s.v, fx.ws.f, scratch); };
  run();  // warm-up: the scratch pages are touched outside the timing
  for (auto _ : st) {
    run();
    benchmark::ClobberMemory();
  }
  set_counters(st, m.spring_count, bytes_springs(m, layout));
}

// How the blocked step is scheduled, so that each schedule is measured against the one before it in one run.
enum class Schedule {
  fused,           // the default: external forces and the update inside the spring pass, automatic chunk size
  unfused,         // the same chunks, external forces and the update as separate passes
  unfused_chunk8k, // separate passes and the earlier fixed 8192-spring chunks (3 passes on 1024^2)
};

// A batch of steps from the saved state; the restore is outside the timing.
void BM_step(benchmark::State& st, Integrator integ, Schedule schedule) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, st.range(1));
  Fixture& fx = fixture(int(st.range(0)), integ);
  Model& m = fx.built.model;
  // The fixture's model is shared by the cases: set the schedule for this case and put the default back after.
  struct Restore {
    Model& m;
    ~Restore() {
      m.fuse_particle_pass = true;
      build_spring_chunks(m);
    }
  } restore{m};
  m.fuse_particle_pass = schedule == Schedule::fused;
  if (schedule == Schedule::unfused_chunk8k) build_spring_chunks(m, 8192);
  State a = fx.warm, b = fx.warm;
  constexpr int batch = 4;
  for (auto _ : st) {
    st.PauseTiming();
    a.x = fx.warm.x;
    a.v = fx.warm.v;
    st.ResumeTiming();
    for (int k = 0; k < batch; ++k) {
      step(m, fx.built.options, a, b, fx.ws, fx.built.options.dt);
      std::swap(a, b);
    }
    benchmark::ClobberMemory();
  }
  set_counters(st, double(batch) * m.particle_count,
               batch * (integ == Integrator::rk4 ? bytes_step_rk4(m) : bytes_step_symplectic(m)));
}

void BM_normals(benchmark::State& st) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, st.range(1));
  Fixture& fx = fixture(int(st.range(0)), Integrator::symplectic);
  const Model& m = fx.built.model;
  for (auto _ : st) {
    eval_normals(m, fx.warm.x, fx.ws.normal);
    benchmark::ClobberMemory();
  }
  set_counters(st, m.particle_count, bytes_normals(m));
}

// One OBJ frame formatted to memory (the file write itself is the disk's speed, not ours); bytes = text size.
void BM_obj_frame(benchmark::State& st) {
  Fixture& fx = fixture(int(st.range(0)), Integrator::symplectic);
  const Model& m = fx.built.model;
  eval_normals(m, fx.warm.x, fx.ws.normal);
  std::size_t size = 0;
  for (auto _ : st) {
    const std::string text = io::format_frame(m, m.cloths[0], "sheet", fx.warm.x, fx.ws.normal, 1);
    size = text.size();
    benchmark::DoNotOptimize(text.data());
  }
  set_counters(st, m.particle_count, double(size));
}

// Sizes x threads: 1 thread and every core; the 1024^2 sheet only where the throughput targets need it.
void sizes_threads(benchmark::internal::Benchmark* b) {
  const int all = tbb::info::default_concurrency();
  for (int n : {64, 256, 1024})
    for (int t : {1, all}) {
      b->Args({n, t});
      if (all == 1) break;
    }
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK_CAPTURE(BM_springs, gather, BenchLayout::gather)->Apply(sizes_threads);
BENCHMARK_CAPTURE(BM_springs, two_phase, BenchLayout::two_phase)->Apply(sizes_threads);
BENCHMARK_CAPTURE(BM_springs, blocked, BenchLayout::blocked)->Apply(sizes_threads);
BENCHMARK_CAPTURE(BM_step, symplectic, Integrator::symplectic, Schedule::fused)->Apply(sizes_threads);
BENCHMARK_CAPTURE(BM_step, rk4, Integrator::rk4, Schedule::fused)->Apply(sizes_threads);
BENCHMARK_CAPTURE(BM_step, symplectic_unfused, Integrator::symplectic, Schedule::unfused)->Apply(sizes_threads);
BENCHMARK_CAPTURE(BM_step, rk4_unfused, Integrator::rk4, Schedule::unfused)->Apply(sizes_threads);
BENCHMARK_CAPTURE(BM_step, symplectic_unfused_chunk8k, Integrator::symplectic, Schedule::unfused_chunk8k)
    ->Apply(sizes_threads);
BENCHMARK_CAPTURE(BM_step, rk4_unfused_chunk8k, Integrator::rk4, Schedule::unfused_chunk8k)->Apply(sizes_threads);
BENCHMARK(BM_normals)->Apply(sizes_threads);
BENCHMARK(BM_obj_frame)->Arg(64)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace clothsim::bench
