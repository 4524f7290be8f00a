// Does a mapped (per-spring) stiffness cost anything, and does the uniform ParamField (stride 0) cost anything
// against plain scalars? The spring kernel on a 256 x 256 grid (~390k springs), one thread, in each layout L
// (0 gather; 1 two-phase; 2 blocked, the default for grids since the vectorised kernels):
//   scalar_reference/L  L = 1, 2: the vectorised kernel of layout L with ke and kd as plain numbers, the lane
//                       block's ke/kd loads gone ("before": no fields)
//   uniform_field/L     the real kernel of layout L with stride-0 ParamFields (what an unmapped scene builds)
//   per_spring_field/L  the same with per-spring arrays (what a stiffness/damping map builds)
// Run: build/bench/clothsim_bench --benchmark_filter=SpringParams --benchmark_repetitions=15
//      --benchmark_min_time=0.1 --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>

#include "bench/kernel_traffic.h"
#include "core/build_model.h"
#include "core/csr.h"
#include "systems/parallel.h"
#include "systems/spring_forces.h"

namespace clothsim {
namespace {

struct SpringBench {
  BuiltScene scene;
  std::vector<Vec3> v, f, spring_force;

  SpringBench() {
    SceneDesc desc;
    ClothDesc cloth;
    cloth.grid_nx = cloth.grid_ny = 256;
    desc.cloths = {cloth};
    scene = build_model(desc, {make_cloth_grid(cloth)});
    build_particle_springs(scene.model);  // the layouts measured here read it; the blocked default does not
    // A stretched, moving state, so every spring does real work.
    for (Index i = 0; i < scene.model.particle_count; ++i) {
      scene.state.x[i] *= 1.01;
      v.push_back(Vec3(std::sin(0.1 * i), 0.01, std::cos(0.07 * i)));
    }
    f.assign(scene.model.particle_count, Vec3::Zero());
    spring_force.assign(scene.model.spring_count, Vec3::Zero());
  }

  void make_per_spring() {
    std::vector<Real> ke, kd;
    for (Index s = 0; s < scene.model.spring_count; ++s) {
      ke.push_back(1000 * (1 + 0.5 * std::sin(0.001 * s)));
      kd.push_back(0.1 * (1 + 0.5 * std::cos(0.001 * s)));
    }
    scene.model.spring_ke = ParamField::from_values(std::move(ke));
    scene.model.spring_kd = ParamField::from_values(std::move(kd));
  }
};

// The vectorised lane block of systems/spring_forces.cpp as it would read with one stiffness and one damping
// for all springs: the same spring_force_lane, so the same bytes; only the ke/kd loads differ.
constexpr Index lane_block = 64;
void eval_block_scalar(const Model& m, std::span<const Vec3> x, std::span<const Vec3> v, Index begin, Index end,
                       Real ke, Real kd, Vec3* out) {
  alignas(64) Real dx[lane_block], dy[lane_block], dz[lane_block], dvx[lane_block], dvy[lane_block],
      dvz[lane_block], rest[lane_block], fx[lane_block], fy[lane_block], fz[lane_block];
  const Index n = end - begin;
  for (Index k = 0; k < n; ++k) {
    const Index s = begin + k, a = m.spring_a[s], b = m.spring_b[s];
    dx[k] = x[b][0] - x[a][0]; dy[k] = x[b][1] - x[a][1]; dz[k] = x[b][2] - x[a][2];
    dvx[k] = v[b][0] - v[a][0]; dvy[k] = v[b][1] - v[a][1]; dvz[k] = v[b][2] - v[a][2];
    rest[k] = m.spring_rest[s];
  }
  for (Index k = 0; k < n; ++k) {
    const SpringLane f = spring_force_lane(dx[k], dy[k], dz[k], dvx[k], dvy[k], dvz[k], rest[k], ke, kd);
    fx[k] = f.fx;
    fy[k] = f.fy;
    fz[k] = f.fz;
  }
  for (Index k = 0; k < n; ++k) out[k] = Vec3(fx[k], fy[k], fz[k]);
}

void eval_two_phase_scalar(const Model& m, Real ke, Real kd, std::span<const Vec3> x, std::span<const Vec3> v,
                           std::span<Vec3> f, std::span<Vec3> spring_force_out) {
  const Index blocks = (m.spring_count + lane_block - 1) / lane_block;
  parallel_over(blocks, 4 * particle_grain / lane_block, [&](Index blk) {
    const Index begin = blk * lane_block;
    eval_block_scalar(m, x, v, begin, std::min(begin + lane_block, m.spring_count), ke, kd,
                      spring_force_out.data() + begin);
  });
  gather_spring_forces(m, spring_force_out, f);
}

void eval_blocked_scalar(const Model& m, Real ke, Real kd, std::span<const Vec3> x, std::span<const Vec3> v,
                         std::span<Vec3> f) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) { f[i] = Vec3::Zero(); });
  const Index passes = Index(m.spring_pass_offset.size()) - 1;
  for (Index p = 0; p < passes; ++p) {
    const Index first = m.spring_pass_offset[p];
    parallel_over(m.spring_pass_offset[p + 1] - first, 1, [&](Index k) {
      const Index chunk = m.spring_pass_chunk[first + k];
      const Index end = m.spring_chunk_offset[chunk + 1];
      Vec3 lane[lane_block];
      for (Index begin = m.spring_chunk_offset[chunk]; begin < end; begin += lane_block) {
        const Index stop = std::min(begin + lane_block, end);
        eval_block_scalar(m, x, v, begin, stop, ke, kd, lane);
        for (Index s = begin; s < stop; ++s) {
          f[m.spring_a[s]] += lane[s - begin];
          f[m.spring_b[s]] -= lane[s - begin];
        }
      }
    });
  }
}

bench::BenchLayout layout_arg(benchmark::State& st) { return bench::BenchLayout(st.range(0)); }

void SpringParams_scalar_reference(benchmark::State& st) {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  SpringBench b;
  const Model& m = b.scene.model;
  const Real ke = m.spring_ke[0], kd = m.spring_kd[0];
  if (m.spring_pass_offset.empty()) st.SkipWithError("expected spring chunks (grids build them)");
  const bool blocked = layout_arg(st) == bench::BenchLayout::blocked;
  for (auto _ : st) {
    if (blocked) eval_blocked_scalar(m, ke, kd, b.scene.state.x, b.v, b.f);
    else eval_two_phase_scalar(m, ke, kd, b.scene.state.x, b.v, b.f, b.spring_force);
    benchmark::DoNotOptimize(b.f.data());
  }
  // The reference must compute what the real kernel computes, bit for bit, or the comparison means nothing.
  std::vector<Vec3> f_real(b.f.size());
  bench::eval_springs_as(layout_arg(st), m, b.scene.state.x, b.v, f_real, b.spring_force);
  if (f_real != b.f) st.SkipWithError("scalar_reference differs from the real kernel");
  st.counters["springs/s"] = benchmark::Counter(double(m.spring_count), benchmark::Counter::kIsIterationInvariantRate);
}

void SpringParams_uniform_field(benchmark::State& st) {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  SpringBench b;
  if (!b.scene.model.spring_ke.uniform()) st.SkipWithError("expected a uniform stiffness");
  for (auto _ : st) {
    bench::eval_springs_as(layout_arg(st), b.scene.model, b.scene.state.x, b.v, b.f, b.spring_force);
    benchmark::DoNotOptimize(b.f.data());
  }
  st.counters["springs/s"] = benchmark::Counter(double(b.scene.model.spring_count), benchmark::Counter::kIsIterationInvariantRate);
}

void SpringParams_per_spring_field(benchmark::State& st) {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  SpringBench b;
  b.make_per_spring();
  if (b.scene.model.spring_ke.uniform()) st.SkipWithError("expected per-spring stiffness");
  for (auto _ : st) {
    bench::eval_springs_as(layout_arg(st), b.scene.model, b.scene.state.x, b.v, b.f, b.spring_force);
    benchmark::DoNotOptimize(b.f.data());
  }
  st.counters["springs/s"] = benchmark::Counter(double(b.scene.model.spring_count), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(SpringParams_scalar_reference)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(SpringParams_uniform_field)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(SpringParams_per_spring_field)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace clothsim
