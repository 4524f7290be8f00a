#pragma once
// The determinism check shared by the tests: a scene stepped at 1 and at 2 worker threads must give the same bytes.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cstring>

#include "systems/step.h"
#include "tests/support/scene_fixtures.h"

namespace clothsim::test {

// True when both hold the same positions (or velocities), byte for byte.
inline bool same_bytes(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

// The state after `steps` steps of the options' dt, with at most `threads` worker threads.
inline State state_after_steps(BuiltScene b, int steps, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  Workspace ws = make_workspace(b.model, b.options);
  State scratch = b.state;
  for (int k = 0; k < steps; ++k) {
    step(b.model, b.options, b.state, scratch, ws, b.options.dt);
    std::swap(b.state, scratch);
  }
  return std::move(b.state);
}

// Checks that the scene's positions and velocities after `steps` steps are the same bytes at 1 and 2 threads.
inline void check_same_bytes_at_1_and_2_threads(const BuiltScene& b, int steps) {
  const State one = state_after_steps(b, steps, 1), two = state_after_steps(b, steps, 2);
  CHECK(std::memcmp(one.x.data(), two.x.data(), one.x.size() * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(one.v.data(), two.v.data(), one.v.size() * sizeof(Vec3)) == 0);
}

}  // namespace clothsim::test
