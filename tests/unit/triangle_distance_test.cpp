// closest_point_and_weights (core/triangle_distance.h): the closest point of each of the seven regions round a
// triangle against hand-placed answers, and its weights, which must rebuild the point and be exact zeros off the
// corners the point lies on (the collider guard reads the feature from them).
#include <doctest/doctest.h>

#include <random>

#include "core/triangle_distance.h"

using namespace clothsim;

namespace {
const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);

void check_region(const Vec3& p, const Vec3& point, const Vec3& weights) {
  CAPTURE(p.transpose());
  const TrianglePoint q = closest_point_and_weights(p, a, b, c);
  CHECK((q.point - point).norm() < 1e-15);
  CHECK((q.weights - weights).norm() < 1e-15);
  for (int k = 0; k < 3; ++k) CHECK((q.weights[k] == 0) == (weights[k] == 0));
  CHECK((closest_point_on_triangle(p, a, b, c) - q.point).norm() == 0);
}
}  // namespace

TEST_CASE("closest point on a triangle: each region's point and weights") {
  check_region(Vec3(-1, -1, 1), a, Vec3(1, 0, 0));
  check_region(Vec3(2, -1, 0), b, Vec3(0, 1, 0));
  check_region(Vec3(-1, 2, 0), c, Vec3(0, 0, 1));
  check_region(Vec3(0.25, -1, 0.5), Vec3(0.25, 0, 0), Vec3(0.75, 0.25, 0));
  check_region(Vec3(-1, 0.5, -2), Vec3(0, 0.5, 0), Vec3(0.5, 0, 0.5));
  check_region(Vec3(1, 1, 0.5), Vec3(0.5, 0.5, 0), Vec3(0, 0.5, 0.5));
  check_region(Vec3(0.25, 0.5, 0.75), Vec3(0.25, 0.5, 0), Vec3(0.25, 0.25, 0.5));
}

TEST_CASE("closest point on a triangle: the weights rebuild the point, and no sampled point is nearer") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> u(-2, 2), unit(0, 1);
  const Vec3 p0(0.1, -0.3, 0.2), p1(1.3, 0.4, -0.1), p2(-0.2, 0.9, 0.6);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const TrianglePoint q = closest_point_and_weights(p, p0, p1, p2);
    CHECK(q.weights.minCoeff() >= -1e-12);
    CHECK(std::abs(q.weights.sum() - 1) < 1e-12);
    CHECK((q.weights[0] * p0 + q.weights[1] * p1 + q.weights[2] * p2 - q.point).norm() < 1e-12);
    const Real d = (p - q.point).norm();
    for (int k = 0; k < 50; ++k) {
      Real s = unit(rng), t = unit(rng);
      if (s + t > 1) s = 1 - s, t = 1 - t;
      CHECK(d <= (p - ((1 - s - t) * p0 + s * p1 + t * p2)).norm() + 1e-12);
    }
  }
}
