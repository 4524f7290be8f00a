// The spring layouts agree bit for bit with each other and with the per-spring function, at any thread count
// (vectorising a kernel must not change a single result: docs/performance.md, "Spring-force layouts").
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstring>

#include "core/csr.h"
#include "core/spring_chunks.h"
#include "systems/spring_forces.h"
#include "tests/support/sheet_scene.h"
#include "tests/support/spring_fixtures.h"
#include "tests/support/thread_bytes.h"

using namespace clothsim;

namespace {

// A 33 x 33 sheet with every particle moved and moving pseudo-randomly, plus one zero-length spring's worth of
// coincident endpoints (particles 5 and 6 placed on top of each other), so no spring sits at rest.
BuiltScene perturbed_sheet() {
  BuiltScene b = bench::build_sheet(33, Integrator::symplectic);
  test::perturb_state(b.state, 12345, 0.01);
  b.state.x[6] = b.state.x[5];
  build_particle_springs(b.model);  // the blocked default goes without it; these tests compare the layouts
  return b;
}

}  // namespace

TEST_CASE("two-phase spring forces equal spring_force() per spring, bit for bit") {
  const BuiltScene b = perturbed_sheet();
  const Model& m = b.model;
  std::vector<Vec3> f(m.particle_count), per_spring(m.spring_count);
  eval_springs_two_phase(m, b.state.x, b.state.v, f, per_spring);
  int zero_length = 0;
  for (Index s = 0; s < m.spring_count; ++s) {
    const Index a = m.spring_a[s], c = m.spring_b[s];
    const Vec3 ref = spring_force(b.state.x[a], b.state.x[c], b.state.v[a], b.state.v[c], m.spring_rest[s],
                                  m.spring_ke[s], m.spring_kd[s]);
    REQUIRE(std::memcmp(ref.data(), per_spring[s].data(), sizeof(Vec3)) == 0);
    if ((a == 5 && c == 6) || (a == 6 && c == 5)) {
      ++zero_length;
      CHECK(per_spring[s] == Vec3::Zero());
    }
  }
  CHECK(zero_length == 1);  // the structural spring 5-6
}

TEST_CASE("gather and two-phase layouts give the same bytes at 1 and 2 threads") {
  const BuiltScene b = perturbed_sheet();
  const Model& m = b.model;
  std::vector<Vec3> scratch(m.spring_count);
  std::vector<Vec3> gather1(m.particle_count), gather2(m.particle_count), two1(m.particle_count),
      two2(m.particle_count);
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    eval_springs_gather(m, b.state.x, b.state.v, gather1);
    eval_springs_two_phase(m, b.state.x, b.state.v, two1, scratch);
  }
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    eval_springs_gather(m, b.state.x, b.state.v, gather2);
    eval_springs_two_phase(m, b.state.x, b.state.v, two2, scratch);
  }
  CHECK(test::same_bytes(gather1, gather2));
  CHECK(test::same_bytes(two1, two2));
  CHECK(test::same_bytes(gather1, two1));
  // Newton's third law: the spring forces of a free system sum to zero (up to rounding).
  Vec3 total = Vec3::Zero();
  for (const Vec3& fi : two1) total += fi;
  CHECK(total.norm() < 1e-9 * m.spring_count);
}

TEST_CASE("blocked layout: chunks of a pass touch disjoint particles, every chunk once") {
  BuiltScene b = perturbed_sheet();
  Model& m = b.model;
  CHECK(m.spring_layout == SpringLayout::blocked);  // a grid's spring order is local: the default
  REQUIRE(build_spring_chunks(m, 256));
  const Index chunks = Index(m.spring_chunk_offset.size()) - 1;
  CHECK(chunks == (m.spring_count + 255) / 256);
  CHECK(Index(m.spring_pass_chunk.size()) == chunks);
  CHECK(m.spring_pass_offset.size() > 2);  // 256-spring chunks span ~2 rows of a 33-wide sheet: several passes
  std::vector<int> seen(chunks, 0);
  for (std::size_t p = 0; p + 1 < m.spring_pass_offset.size(); ++p) {
    std::vector<int> owner(m.particle_count, -1);  // which chunk of this pass touched a particle
    for (Index k = m.spring_pass_offset[p]; k < m.spring_pass_offset[p + 1]; ++k) {
      const Index c = m.spring_pass_chunk[k];
      ++seen[c];
      for (Index s = m.spring_chunk_offset[c]; s < m.spring_chunk_offset[c + 1]; ++s)
        for (Index i : {m.spring_a[s], m.spring_b[s]}) {
          CHECK((owner[i] == -1 || owner[i] == c));
          owner[i] = c;
        }
    }
  }
  for (int n : seen) CHECK(n == 1);
}

TEST_CASE("blocked layout: same bytes at 1, 2 and 3 threads, equal to gather up to summation order") {
  BuiltScene b = perturbed_sheet();
  Model& m = b.model;
  REQUIRE(build_spring_chunks(m, 256));
  std::vector<Vec3> gather(m.particle_count), blocked[3];
  eval_springs_gather(m, b.state.x, b.state.v, gather);
  for (int t = 1; t <= 3; ++t) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, t);
    blocked[t - 1].resize(m.particle_count);
    eval_springs_blocked(m, b.state.x, b.state.v, blocked[t - 1]);
  }
  CHECK(test::same_bytes(blocked[0], blocked[1]));
  CHECK(test::same_bytes(blocked[0], blocked[2]));
  double worst = 0;
  for (Index i = 0; i < m.particle_count; ++i)
    worst = std::max(worst, (blocked[0][i] - gather[i]).norm() / std::max(1.0, gather[i].norm()));
  CHECK(worst < 1e-12);  // a handful of springs, each rounded once: only the order of the sum differs
}

TEST_CASE("blocked layout: bitwise the plain sequential sum in (pass, chunk, spring) order") {
  // The kernel holds a run of springs' common first end in registers and zeroes f chunk by chunk; neither may
  // change a bit against f[a] += f_s, f[b] -= f_s done one spring at a time in the documented order.
  BuiltScene b = perturbed_sheet();
  Model& m = b.model;
  // The three ways the lane block reads ke and kd: the bench sheet's own fields (flex springs at 0.1 x the
  // stiffness: a palette of two values; uniform damping), then both per spring (a map), then both a palette.
  enum class Fields { sheet, per_element, palette };
  for (const Fields fields : {Fields::sheet, Fields::per_element, Fields::palette}) {
    CAPTURE(int(fields));
    REQUIRE(build_spring_chunks(m, fields == Fields::sheet ? 256 : 0));
    if (fields == Fields::sheet) {
      REQUIRE(m.spring_ke.paletted());
      REQUIRE(m.spring_kd.uniform());
    } else {
      ParamFieldBuilder ke, kd;
      for (Index s = 0; s < m.spring_count; ++s) {
        // per element: more distinct values than a palette holds; palette: a few
        const bool many = fields == Fields::per_element;
        ke.push(500 + s % (many ? 97 : 7));
        kd.push(0.1 + 0.001 * (s % (many ? 89 : 5)));
      }
      m.spring_ke = ke.finish();
      m.spring_kd = kd.finish();
      REQUIRE(m.spring_ke.paletted() == (fields == Fields::palette));
      REQUIRE(m.spring_kd.paletted() == (fields == Fields::palette));
      REQUIRE_FALSE(m.spring_ke.uniform());
      REQUIRE_FALSE(m.spring_kd.uniform());
    }
    std::vector<Vec3> reference(m.particle_count, Vec3::Zero()), blocked(m.particle_count);
    for (Index c : m.spring_pass_chunk)
      for (Index s = m.spring_chunk_offset[c]; s < m.spring_chunk_offset[c + 1]; ++s) {
        const Index a = m.spring_a[s], e = m.spring_b[s];
        const Vec3 fs = spring_force(b.state.x[a], b.state.x[e], b.state.v[a], b.state.v[e], m.spring_rest[s],
                                     m.spring_ke[s], m.spring_kd[s]);
        reference[a] += fs;
        reference[e] -= fs;
      }
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    eval_springs_blocked(m, b.state.x, b.state.v, blocked);
    CHECK(test::same_bytes(reference, blocked));
  }
}

TEST_CASE("blocked layout is refused when the spring order has no locality") {
  BuiltScene b = perturbed_sheet();
  Model& m = b.model;
  // Interleave springs from the two ends of the sheet: every chunk spans almost all particles.
  std::vector<Index> a, c;
  for (Index lo = 0, hi = m.spring_count - 1; lo <= hi; ++lo, --hi) {
    a.push_back(m.spring_a[lo]); c.push_back(m.spring_b[lo]);
    if (hi != lo) { a.push_back(m.spring_a[hi]); c.push_back(m.spring_b[hi]); }
  }
  m.spring_a = a;
  m.spring_b = c;
  CHECK_FALSE(build_spring_chunks(m, 256));
  CHECK(build_spring_chunks(m, 256, 1000));  // allowed as many passes as chunks, it still succeeds
}
