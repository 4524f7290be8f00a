// Collision broad phase and full pass on N x N self-colliding sheets, crumpled so that contacts exist:
// hash rebuild, BVH refit, and the whole collide stage with either broad phase. Vertices per second.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "core/build_collision.h"
#include "core/build_model.h"
#include "systems/collision/bvh.h"
#include "systems/collision/collide.h"
#include "systems/collision/spatial_hash.h"

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
  Workspace ws = make_workspace(s.built.model, s.built.options);
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
  Workspace ws = make_workspace(s.built.model, s.built.options);
  build_broad_phase(s.built.model, s.in, s.out, ws.collision);
  for (auto _ : st) {
    refit_bvh(s.built.model.collision.cloth_tree, ws.collision.prim_box, ws.collision.cloth_node_box);
    benchmark::DoNotOptimize(ws.collision.cloth_node_box.data());
  }
  set_counters(st, s.built.model);
}

// Times the whole collide stage from s.in to s.out, restored before each call, after one warm-up call that
// grows the hash once.
void time_collide(benchmark::State& st, const Sheet& s) {
  Workspace ws = make_workspace(s.built.model, s.built.options);
  State out = s.out;
  CollideCounts first = collide(s.built.model, s.in, out, ws, 1e-3);
  std::int64_t contacts = first.contacts;
  ZoneFigures zones = first.zones;
  for (auto _ : st) {
    st.PauseTiming();
    out.x = s.out.x;
    out.v = s.out.v;
    st.ResumeTiming();
    const CollideCounts c = collide(s.built.model, s.in, out, ws, 1e-3);
    contacts += c.contacts;
    zones.add(c.zones);
  }
  set_counters(st, s.built.model);
  st.counters["contacts_per_pass"] = benchmark::Counter(double(contacts) / double(st.iterations() + 1));
  // Calls that ran the impact zones (crossings left after the continuous passes), and their passes per call.
  st.counters["zone_calls"] = benchmark::Counter(double(zones.steps) / double(st.iterations() + 1));
  st.counters["zone_passes"] = benchmark::Counter(double(zones.passes) / double(st.iterations() + 1));
  st.SetLabel(s.built.model.collision.broad_phase == BroadPhase::hash ? "hash" : "bvh");
}

// The whole stage: boxes, broad phase, collisionIterations passes of proximity and response.
void BM_CollisionPass(benchmark::State& st) {
  const BroadPhase broad = st.range(1) == 0 ? BroadPhase::hash : BroadPhase::bvh;
  time_collide(st, make_sheet(int(st.range(0)), broad));
}

// A UV sphere mesh of radius r at the origin, `rings` x 2 `rings` quads, counter-clockwise outward.
MeshData sphere_mesh(Real r, int rings) {
  MeshData mesh;
  const int seg = 2 * rings;
  mesh.positions.push_back(Vec3(0, r, 0));
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < seg; ++j) {
      const Real th = M_PI * i / rings, ph = 2 * M_PI * j / seg;
      mesh.positions.push_back(r * Vec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)));
    }
  mesh.positions.push_back(Vec3(0, -r, 0));
  auto ring = [&](int i, int j) { return Index(1 + (i - 1) * seg + j % seg); };
  const Index bottom = Index(mesh.positions.size()) - 1;
  auto tri = [&](Index a, Index b, Index c) { mesh.tri_index.insert(mesh.tri_index.end(), {a, b, c}); };
  for (int j = 0; j < seg; ++j) {
    tri(0, ring(1, j + 1), ring(1, j));
    for (int i = 1; i < rings - 1; ++i) {
      tri(ring(i, j), ring(i, j + 1), ring(i + 1, j + 1));
      tri(ring(i, j), ring(i + 1, j + 1), ring(i + 1, j));
    }
    tri(bottom, ring(rings - 1, j), ring(rings - 1, j + 1));
  }
  return mesh;
}

// The whole stage against a collider mesh finer than the cloth, as an animated body is: an N x N sheet of 1 m
// (no self-collision, thickness 5 mm) lying on a sphere mesh of radius 0.8 m with ~1 cm triangles (rings = 128),
// every vertex within the thickness of the surface, moved a little in the step. Cloth vertices meet collider
// triangles, collider vertices meet cloth triangles, and edges meet edges.
void BM_ColliderPass(benchmark::State& st) {
  const int n = int(st.range(0));
  SceneDesc scene;
  scene.simulation.broad_phase = st.range(1) == 0 ? BroadPhase::hash : BroadPhase::bvh;
  ColliderDesc body;
  body.name = "ball";
  body.shape = ColliderShape::mesh;
  scene.colliders.push_back(body);
  ClothDesc c;
  c.name = "sheet";
  c.grid_nx = c.grid_ny = n;
  c.thickness = 0.005;
  scene.cloths.push_back(c);
  Sheet s;
  s.built = build_model(scene, {make_cloth_grid(c)});
  const Real r = 0.8;
  build_collision(scene, {ColliderMeshes{sphere_mesh(r, 128), 0, 0}}, s.built.state.x, s.built.model);
  std::mt19937 rng(3);
  std::uniform_real_distribution<Real> u(-1, 1);
  s.in = s.built.state;
  s.out = s.in;
  for (std::size_t i = 0; i < s.in.x.size(); ++i) {
    Vec3& p = s.in.x[i];
    p.y() = std::sqrt(r * r - p.x() * p.x() - p.z() * p.z()) + c.thickness * (0.5 + 0.5 * u(rng));
    s.out.x[i] = p + 0.2 * c.thickness * Vec3(u(rng), u(rng), u(rng));
    s.out.v[i] = (s.out.x[i] - p) / 1e-3;
  }
  time_collide(st, s);
}

}  // namespace

BENCHMARK(BM_HashRebuild)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BvhRefit)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CollisionPass)->Args({256, 0})->Args({256, 1})->Args({1024, 0})->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ColliderPass)->Args({64, 0})->Args({64, 1})->Unit(benchmark::kMillisecond);
