// Collision broad phase and full pass on N x N self-colliding sheets, crumpled so that contacts exist:
// hash rebuild, BVH refit, and the whole collide stage with either broad phase. Vertices per second.
#include <benchmark/benchmark.h>

#include <random>

#include "core/build_collision.h"
#include "core/build_model.h"
#include "systems/bvh.h"
#include "systems/collide.h"
#include "systems/spatial_hash.h"

namespace {

using namespace clothsim;

struct Sheet {
  BuiltScene built;
  State in, out;
};

// An N x N sheet of 1 m with self-collision, heights scattered over two cell sizes, moved a little in the step.
Sheet make_sheet(int n, BroadPhase broad) {
  SceneDesc scene;
  scene.simulation.broad_phase = broad;
  ClothDesc c;
  c.name = "sheet";
  c.grid_nx = c.grid_ny = n;
  c.self_collision = true;
  c.thickness = 0.5 / n;
  scene.cloths.push_back(c);
  Sheet s;
  s.built = build_model(scene, {make_cloth_grid(c)});
  build_collision(scene, {}, s.built.state.x, s.built.model);
  std::mt19937 rng(3);
  std::uniform_real_distribution<Real> u(-1, 1);
  s.in = s.built.state;
  s.out = s.in;
  const Real cell = 1.0 / n;
  for (std::size_t i = 0; i < s.in.x.size(); ++i) {
    s.in.x[i].y() += 2 * cell * u(rng);
    s.out.x[i] = s.in.x[i] + 0.1 * cell * Vec3(u(rng), u(rng), u(rng));
    s.out.v[i] = (s.out.x[i] - s.in.x[i]) / 1e-3;
  }
  return s;
}

void set_counters(benchmark::State& st, const Model& m) {
  st.SetItemsProcessed(st.iterations() * m.particle_count);
  st.counters["vertices"] = m.particle_count;
}

void BM_HashRebuild(benchmark::State& st) {
  Sheet s = make_sheet(int(st.range(0)), BroadPhase::hash);
  Workspace ws = make_workspace(s.built.model);
  build_broad_phase(s.built.model, s.in, s.out, ws.collision);  // sizes the entry arrays once
  for (auto _ : st) {
    build_spatial_hash(s.built.model.collision, ws.collision);
    benchmark::DoNotOptimize(ws.collision.hash.entry_prim.data());
  }
  set_counters(st, s.built.model);
  st.counters["entries"] = ws.collision.hash.entry_count;
}

void BM_BvhRefit(benchmark::State& st) {
  Sheet s = make_sheet(int(st.range(0)), BroadPhase::bvh);
  Workspace ws = make_workspace(s.built.model);
  build_broad_phase(s.built.model, s.in, s.out, ws.collision);
  for (auto _ : st) {
    refit_bvh(s.built.model.collision, ws.collision);
    benchmark::DoNotOptimize(ws.collision.node_box.data());
  }
  set_counters(st, s.built.model);
}

// The whole stage: boxes, broad phase, collisionIterations passes of proximity and response.
void BM_CollisionPass(benchmark::State& st) {
  const BroadPhase broad = st.range(1) == 0 ? BroadPhase::hash : BroadPhase::bvh;
  Sheet s = make_sheet(int(st.range(0)), broad);
  Workspace ws = make_workspace(s.built.model);
  State out = s.out;
  collide(s.built.model, s.in, out, ws, 1e-3);  // warm-up: grows the hash once
  for (auto _ : st) {
    st.PauseTiming();
    out.x = s.out.x;
    out.v = s.out.v;
    st.ResumeTiming();
    collide(s.built.model, s.in, out, ws, 1e-3);
  }
  set_counters(st, s.built.model);
  st.counters["contacts_per_pass"] =
      benchmark::Counter(double(ws.collision.contacts_found) / double(st.iterations() + 1));
  st.SetLabel(broad == BroadPhase::hash ? "hash" : "bvh");
}

}  // namespace

BENCHMARK(BM_HashRebuild)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BvhRefit)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CollisionPass)->Args({256, 0})->Args({256, 1})->Args({1024, 0})->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
