// Does a mapped (per-spring) stiffness cost anything, and does the uniform ParamField (stride 0) cost anything
// against plain scalars? The spring kernel on a 256 x 256 grid (~390k springs), one thread:
//   scalar_reference    a copy of the two-phase kernel taking ke and kd as plain numbers ("before": no fields)
//   uniform_field/L     the real kernel of layout L (0 gather, the default; 1 two-phase) with stride-0
//                       ParamFields (what an unmapped scene builds)
//   per_spring_field/L  the same with per-spring arrays (what a stiffness/damping map builds)
// Run: build/bench/clothsim_bench --benchmark_filter=SpringParams --benchmark_repetitions=15
//      --benchmark_min_time=0.1 --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>

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

// The kernel as it would read with one stiffness and one damping for all springs.
void eval_springs_scalar(const Model& m, Real ke, Real kd, std::span<const Vec3> x, std::span<const Vec3> v,
                         std::span<Vec3> f, std::span<Vec3> spring_force_out) {
  parallel_over(m.spring_count, 4 * particle_grain, [&](Index s) {
    const Index a = m.spring_a[s], b = m.spring_b[s];
    spring_force_out[s] = spring_force(x[a], x[b], v[a], v[b], m.spring_rest[s], ke, kd);
  });
  gather_spring_forces(m, spring_force_out, f);
}

void SpringParams_scalar_reference(benchmark::State& st) {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  SpringBench b;
  const Real ke = b.scene.model.spring_ke[0], kd = b.scene.model.spring_kd[0];
  for (auto _ : st) {
    eval_springs_scalar(b.scene.model, ke, kd, b.scene.state.x, b.v, b.f, b.spring_force);
    benchmark::DoNotOptimize(b.f.data());
  }
  st.counters["springs/s"] = benchmark::Counter(double(b.scene.model.spring_count), benchmark::Counter::kIsIterationInvariantRate);
}

void SpringParams_uniform_field(benchmark::State& st) {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  SpringBench b;
  b.scene.model.spring_layout = st.range(0) == 0 ? SpringLayout::gather : SpringLayout::two_phase;
  if (!b.scene.model.spring_ke.uniform()) st.SkipWithError("expected a uniform stiffness");
  for (auto _ : st) {
    eval_springs(b.scene.model, b.scene.state.x, b.v, b.f, b.spring_force);
    benchmark::DoNotOptimize(b.f.data());
  }
  st.counters["springs/s"] = benchmark::Counter(double(b.scene.model.spring_count), benchmark::Counter::kIsIterationInvariantRate);
}

void SpringParams_per_spring_field(benchmark::State& st) {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  SpringBench b;
  b.make_per_spring();
  b.scene.model.spring_layout = st.range(0) == 0 ? SpringLayout::gather : SpringLayout::two_phase;
  if (b.scene.model.spring_ke.uniform()) st.SkipWithError("expected per-spring stiffness");
  for (auto _ : st) {
    eval_springs(b.scene.model, b.scene.state.x, b.v, b.f, b.spring_force);
    benchmark::DoNotOptimize(b.f.data());
  }
  st.counters["springs/s"] = benchmark::Counter(double(b.scene.model.spring_count), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(SpringParams_scalar_reference)->Unit(benchmark::kMillisecond);
BENCHMARK(SpringParams_uniform_field)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(SpringParams_per_spring_field)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace clothsim
