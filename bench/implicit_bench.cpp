// One backward-Euler step (Baraff & Witkin 1998) of a hanging sheet, in the two ways CG can apply the matrix:
// per-spring blocks built once per solve, or recomputed from the positions in every product (matrix-free); and
// with the block-Jacobi or the multigrid preconditioner (systems/multigrid.h).
// The input state is fixed (a sheet that has sagged for 0.25 s), so every timed step does the same work.
#include <benchmark/benchmark.h>

#include "core/build_model.h"
#include "systems/integrate_implicit.h"
#include "systems/step.h"

namespace {

using namespace clothsim;

struct Sheet {
  BuiltScene s;
  Workspace ws;
};

Sheet make_sheet(int n, Preconditioner preconditioner) {
  SceneDesc scene;
  scene.path = "bench";
  scene.simulation.integrator = Integrator::implicit;
  scene.simulation.cg_tolerance = 1e-6;
  scene.simulation.preconditioner = preconditioner;
  ClothDesc c;
  c.grid_nx = c.grid_ny = n;
  c.stiffness = 5000;
  c.bend_scale = 0.2;
  c.damping = 0.05;
  c.pins = {0, n - 1};
  c.transform.rotate = Vec3(90, 0, 0);
  scene.cloths = {c};
  Sheet sh{build_model(scene, {make_cloth_grid(c)}), {}};
  sh.ws = make_workspace(sh.s.model, sh.s.options);
  State scratch = sh.s.state;
  for (int k = 0; k < 25; ++k) {  // warm up: let it sag, so springs are stretched and CG has real work
    step(sh.s.model, sh.s.options, sh.s.state, scratch, sh.ws, 0.01);
    std::swap(sh.s.state, scratch);
  }
  return sh;
}

void BM_implicit_step(benchmark::State& bs, ImplicitLayout layout, Preconditioner preconditioner) {
  Sheet sh = make_sheet(int(bs.range(0)), preconditioner);
  State out = sh.s.state;
  long long cg = 0;
  for (auto _ : bs) {
    const StepResult r = integrate_implicit(sh.s.model, sh.s.options.solver, sh.s.state, out, sh.ws, 0.01, layout);
    cg += r.solve.cg_iterations;
    benchmark::DoNotOptimize(out.v.data());
  }
  bs.counters["cg_iterations"] = double(cg) / double(bs.iterations());
  bs.counters["particles"] = double(sh.s.model.particle_count);
}

}  // namespace

BENCHMARK_CAPTURE(BM_implicit_step, spring_blocks, ImplicitLayout::spring_blocks, Preconditioner::jacobi)
    ->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->MinTime(0.5);
BENCHMARK_CAPTURE(BM_implicit_step, recompute, ImplicitLayout::recompute, Preconditioner::jacobi)
    ->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->MinTime(0.5);
BENCHMARK_CAPTURE(BM_implicit_step, multigrid, ImplicitLayout::spring_blocks, Preconditioner::multigrid)
    ->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->MinTime(0.5);
