// The fused force stage (systems/forces.h): external forces and the integrator's update inside the blocked
// spring pass must give the bytes of the separate passes, at any thread count. Same summation order
// in both, so the comparison is bitwise.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cstring>

#include "core/spring_chunks.h"
#include "systems/step.h"
#include "tests/support/sheet_scene.h"
#include "tests/support/spring_fixtures.h"

using namespace clothsim;

namespace {

// A 33 x 33 sheet, pinned at two corners, moved and moving pseudo-randomly, with wind (normals), random forces
// and air damping, so every term of the external acceleration is live. 256-spring chunks: many chunks, 3 passes.
BuiltScene windy_sheet(Integrator integrator) {
  SceneDesc s = bench::sheet_scene(33, integrator);
  s.forces.wind_velocity = Vec3(1, 0, 0.5);
  s.forces.wind_strength = 0.3;
  s.forces.random.amplitude = 0.2;
  BuiltScene b = build_model(s, {make_cloth_grid(s.cloths[0])});
  REQUIRE(build_spring_chunks(b.model, 256));
  REQUIRE(b.model.spring_pass_offset.size() > 3);
  test::perturb_state(b.state, 777, 0.01);
  return b;
}

State run_on_threads(const Model& m, const SimOptions& o, State s, int steps, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  Workspace ws = make_workspace(m, o);
  test::run_steps(m, o, s, ws, o.dt, steps);
  return s;
}

bool same_bytes(const State& a, const State& b) {
  auto eq = [](const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
    return p.size() == q.size() && std::memcmp(p.data(), q.data(), p.size() * sizeof(Vec3)) == 0;
  };
  return eq(a.x, b.x) && eq(a.v, b.v);
}

}  // namespace

TEST_CASE("fused force stage: same bytes as separate passes, at 1, 2 and 3 threads") {
  for (Integrator integ : {Integrator::symplectic, Integrator::rk4}) {
    CAPTURE(int(integ));
    BuiltScene b = windy_sheet(integ);
    Model& m = b.model;
    REQUIRE(m.spring_layout == SpringLayout::blocked);
    m.fuse_particle_pass = false;
    const State reference = run_on_threads(m, b.options, b.state, 3, 1);
    m.fuse_particle_pass = true;
    for (int t = 1; t <= 3; ++t) CHECK(same_bytes(run_on_threads(m, b.options, b.state, 3, t), reference));
    // The state moved: the comparison is not of two copies of the start.
    CHECK((reference.x[500] - b.state.x[500]).norm() > 1e-9);
  }
}

TEST_CASE("fused force stage: every particle opened and closed once, after its last spring") {
  BuiltScene b = windy_sheet(Integrator::symplectic);
  const Model& m = b.model;
  const Index chunks = Index(m.spring_chunk_offset.size()) - 1;
  // Position of each chunk in pass order, and the last position of a chunk holding a spring of each particle.
  std::vector<Index> order(chunks);
  for (Index k = 0; k < chunks; ++k) order[m.spring_pass_chunk[k]] = k;
  std::vector<Index> last_spring(m.particle_count, -1);
  for (Index c = 0; c < chunks; ++c)
    for (Index s = m.spring_chunk_offset[c]; s < m.spring_chunk_offset[c + 1]; ++s)
      for (Index i : {m.spring_a[s], m.spring_b[s]}) last_spring[i] = std::max(last_spring[i], order[c]);
  auto owners = [&](const std::vector<Index>& offset, const std::vector<Index>& range) {
    std::vector<Index> owner(m.particle_count, -1);
    for (Index c = 0; c <= chunks; ++c)
      for (Index r = offset[c]; r < offset[c + 1]; ++r)
        for (Index i = range[2 * r]; i < range[2 * r + 1]; ++i) {
          CHECK(owner[i] == -1);
          owner[i] = c;
        }
    return owner;
  };
  const auto open = owners(m.spring_chunk_open_offset, m.spring_chunk_open_range);
  const auto close = owners(m.spring_chunk_close_offset, m.spring_chunk_close_range);
  for (Index i = 0; i < m.particle_count; ++i) {
    REQUIRE(open[i] >= 0);
    REQUIRE(close[i] >= 0);
    REQUIRE(close[i] < chunks);  // a grid has no particle without springs
    CHECK(order[open[i]] <= order[close[i]]);
    CHECK(order[close[i]] >= last_spring[i]);
  }
  // Within its closing chunk, a particle is closed after the block of the chunk's last spring touching it, and
  // every closing particle is closed by the chunk's last block.
  constexpr Index block = spring_block_size;
  for (Index c = 0; c < chunks; ++c) {
    std::vector<Index> closing;  // in cursor order
    for (Index r = m.spring_chunk_close_offset[c]; r < m.spring_chunk_close_offset[c + 1]; ++r)
      for (Index i = m.spring_chunk_close_range[2 * r]; i < m.spring_chunk_close_range[2 * r + 1]; ++i)
        closing.push_back(i);
    const Index begin = m.spring_chunk_offset[c], end = m.spring_chunk_offset[c + 1];
    Index before = 0;
    for (Index first = begin; first < end; first += block) {
      const Index ready = m.spring_block_close[first / block];
      CHECK(ready >= before);
      for (Index k = 0; k < ready; ++k)
        for (Index s = std::min(first + block, end); s < end; ++s)
          REQUIRE((m.spring_a[s] != closing[k] && m.spring_b[s] != closing[k]));
      before = ready;
    }
    CHECK(before == Index(closing.size()));
  }
}

TEST_CASE("fused force stage: particles of no chunk fall freely") {
  // Keep the first half of the springs only: the second half of the sheet lies in no chunk's span.
  BuiltScene b = windy_sheet(Integrator::symplectic);
  Model& m = b.model;
  m.wind_strength = 0;
  m.random.amplitude = 0;
  m.spring_count /= 2;
  m.spring_a.resize(m.spring_count);
  m.spring_b.resize(m.spring_count);
  m.spring_rest.resize(m.spring_count);
  REQUIRE(build_spring_chunks(m, 256));
  const Index free_particle = m.particle_count - 10;  // far from the kept springs, not pinned
  REQUIRE(m.spring_chunk_close_offset.back() > m.spring_chunk_close_offset[m.spring_chunk_offset.size() - 1]);
  const State after = run_on_threads(m, b.options, b.state, 1, 2);
  const Vec3 v0 = b.state.v[free_particle];
  const Vec3 v1 = v0 + b.options.dt * (m.gravity - m.air_damping * v0);  // symplectic Euler, no spring force
  CHECK(std::memcmp(after.v[free_particle].data(), v1.data(), sizeof(Vec3)) == 0);
  const Vec3 x1 = b.state.x[free_particle] + b.options.dt * v1;
  CHECK(std::memcmp(after.x[free_particle].data(), x1.data(), sizeof(Vec3)) == 0);
}
