// The spring layouts agree bit for bit with each other and with the per-spring function, at any thread count
// (issue 7: the vectorised two-phase block must not change a single result).
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cstring>

#include "bench/sheet_scene.h"
#include "systems/spring_forces.h"

using namespace clothsim;

namespace {

// A 33 x 33 sheet with every particle moved and moving pseudo-randomly, plus one zero-length spring's worth of
// coincident endpoints (particles 5 and 6 placed on top of each other), so no spring sits at rest.
BuiltScene perturbed_sheet() {
  BuiltScene b = bench::build_sheet(33, Integrator::symplectic);
  std::uint64_t r = 12345;
  auto next = [&r] {
    r = r * 6364136223846793005ull + 1442695040888963407ull;
    return double(r >> 11) / double(1ull << 53) - 0.5;
  };
  for (Index i = 0; i < b.model.particle_count; ++i) {
    b.state.x[i] += 0.01 * Vec3(next(), next(), next());
    b.state.v[i] = Vec3(next(), next(), next());
  }
  b.state.x[6] = b.state.x[5];
  return b;
}

bool same_bytes(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
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
  CHECK(same_bytes(gather1, gather2));
  CHECK(same_bytes(two1, two2));
  CHECK(same_bytes(gather1, two1));
  // Newton's third law: the spring forces of a free system sum to zero (up to rounding).
  Vec3 total = Vec3::Zero();
  for (const Vec3& fi : two1) total += fi;
  CHECK(total.norm() < 1e-9 * m.spring_count);
}
