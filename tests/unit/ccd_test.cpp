// Continuous detection against hand-computed cases: the coplanarity cubic and its roots, the edge pairs' test.
#include <doctest/doctest.h>

#include "systems/collision/ccd.h"
#include "systems/collision/continuous_pairs.h"

using namespace clothsim;

TEST_CASE("cubic roots in [0, 1]: (t - 0.2)(t - 0.5)(t - 0.9) and a cubic without roots there") {
  // (t - 0.2)(t - 0.5)(t - 0.9) = t^3 - 1.6 t^2 + 0.73 t - 0.09
  const Real k[4] = {-0.09, 0.73, -1.6, 1};
  Real r[3];
  REQUIRE(cubic_roots_01(k, r) == 3);
  CHECK(r[0] == doctest::Approx(0.2));
  CHECK(r[1] == doctest::Approx(0.5));
  CHECK(r[2] == doctest::Approx(0.9));
  const Real none[4] = {1, 0, 0, 1};  // 1 + t^3 > 0 on [0, 1]
  CHECK(cubic_roots_01(none, r) == 0);
}

TEST_CASE("vertex-triangle CCD finds a diagonal crossing that the end-of-step proximity misses") {
  // Triangle in y = 0 with corners (0,0,0), (0,0,1), (1,0,0); the vertex moves from (-0.8, 0.5, 0.2) to
  // (1.2, -0.5, 0.2): at t = 0.5 it is at (0.2, 0, 0.2), inside, and it ends outside the triangle's prism.
  const Vec3 x0[4] = {Vec3(-0.8, 0.5, 0.2), Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0)};
  const Vec3 x1[4] = {Vec3(1.2, -0.5, 0.2), Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0)};
  Real t = -1;
  TriangleProximity hit;
  REQUIRE(vertex_triangle_ccd(x0, x1, 0.01, t, hit));
  CHECK(t == doctest::Approx(0.5));
  TriangleProximity p;
  CHECK_FALSE(vertex_triangle_proximity(x1[0], x1[1], x1[2], x1[3], 0.01, p));  // ends outside the prism
  // The same path shifted past the triangle's edge never hits it.
  Vec3 y0[4] = {x0[0] + Vec3(0, 0, 1), x0[1], x0[2], x0[3]}, y1[4] = {x1[0] + Vec3(0, 0, 1), x1[1], x1[2], x1[3]};
  CHECK_FALSE(vertex_triangle_ccd(y0, y1, 0.01, t, hit));
}

TEST_CASE("vertex-triangle CCD with a moving triangle: a rising triangle meets a resting vertex") {
  // The vertex rests at y = 0.5; the triangle rises from y = 0 to y = 1: coplanar at t = 0.5.
  const Vec3 x0[4] = {Vec3(0.2, 0.5, 0.2), Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0)};
  const Vec3 x1[4] = {Vec3(0.2, 0.5, 0.2), Vec3(0, 1, 0), Vec3(0, 1, 1), Vec3(1, 1, 0)};
  Real t = -1;
  TriangleProximity hit;
  REQUIRE(vertex_triangle_ccd(x0, x1, 0.01, t, hit));
  CHECK(t == doctest::Approx(0.5));
}

TEST_CASE("edge-edge CCD: a falling edge crosses a resting one at the hand-computed time and point") {
  // Edge P rests on the x axis from (0,0,0) to (1,0,0). Edge Q runs along z from (0.25, y, -1) to (0.25, y, 3)
  // with y = 0.3 - 0.4 t: coplanar at t = 0.75, where the lines cross at x = 0.25 (s = 0.25 along P) and z = 0
  // (u = 0.25 along Q). At the end (y = -0.1) the edges are 0.1 apart: the end-of-step proximity sees nothing.
  const Vec3 x0[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.25, 0.3, -1), Vec3(0.25, 0.3, 3)};
  const Vec3 x1[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.25, -0.1, -1), Vec3(0.25, -0.1, 3)};
  Real t = -1;
  EdgeProximity hit;
  REQUIRE(edge_edge_ccd(x0, x1, 0.01, t, hit));
  CHECK(t == doctest::Approx(0.75));
  CHECK(hit.s == doctest::Approx(0.25));
  CHECK(hit.t == doctest::Approx(0.25));
  CHECK(hit.d == doctest::Approx(0).epsilon(1e-9));
  EdgeProximity end;
  REQUIRE(edge_edge_proximity(x1[0], x1[1], x1[2], x1[3], end));
  CHECK(end.d == doctest::Approx(0.1));
  // The same motion with Q past P's end (x = 1.5): coplanar at t = 0.75 too, but the segments stay 0.5 apart.
  Vec3 y0[4] = {x0[0], x0[1], x0[2] + Vec3(1.25, 0, 0), x0[3] + Vec3(1.25, 0, 0)};
  Vec3 y1[4] = {x1[0], x1[1], x1[2] + Vec3(1.25, 0, 0), x1[3] + Vec3(1.25, 0, 0)};
  CHECK_FALSE(edge_edge_ccd(y0, y1, 0.01, t, hit));
}

TEST_CASE("edge-edge CCD with both edges moving: they meet at t = 1/3") {
  // P falls from y = 0.5 at 1.5 per step, Q rises from y = -0.5 at 1.5 per step, crossed at right angles
  // through the origin: heights meet when 0.5 - 1.5 t = -0.5 + 1.5 t, t = 1/3, both at their midpoints.
  const Vec3 x0[4] = {Vec3(-1, 0.5, 0), Vec3(1, 0.5, 0), Vec3(0, -0.5, -1), Vec3(0, -0.5, 1)};
  const Vec3 x1[4] = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, -1), Vec3(0, 1, 1)};
  Real t = -1;
  EdgeProximity hit;
  REQUIRE(edge_edge_ccd(x0, x1, 1e-6, t, hit));
  CHECK(t == doctest::Approx(1.0 / 3));
  CHECK(hit.s == doctest::Approx(0.5));
  CHECK(hit.t == doctest::Approx(0.5));
  // Parallel edges sliding past each other in parallel planes never meet.
  const Vec3 p0[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0.1, 0.2), Vec3(1, 0.1, 0.2)};
  const Vec3 p1[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0.1, -0.2), Vec3(1.5, 0.1, -0.2)};
  CHECK_FALSE(edge_edge_ccd(p0, p1, 0.01, t, hit));
}

TEST_CASE("edge-edge CCD: an edge sliding through another within their common plane is caught where it meets it") {
  // P rests on the x axis from (0,0,0) to (1,0,0). Q, a 0.1 m edge along z at x = 0.5 in the same plane y = 0,
  // slides by -0.6 in z over the step: its near end (z = 0.2 - 0.6 t) reaches P at t = 1/3, its far end
  // (z = 0.3 - 0.6 t) leaves P at t = 1/2, and it ends 0.3 past P, where the end-of-step proximity sees nothing.
  // All four points stay in y = 0: the coplanarity cubic is zero for every t and its only "root" t = 0 (Q 0.2
  // away) missed the crossing; the CCD now solves where an endpoint crosses the other edge's line in the plane.
  const Vec3 x0[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0.2), Vec3(0.5, 0, 0.3)};
  const Vec3 x1[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, -0.4), Vec3(0.5, 0, -0.3)};
  Real k[4];
  coplanarity_cubic(x0, x1, k);
  for (Real c : k) CHECK(c == 0);
  CHECK(coplanar_throughout(x0, x1));
  Real t = -1;
  EdgeProximity hit;
  REQUIRE(edge_edge_ccd(x0, x1, 0.01, t, hit));
  CHECK(t == doctest::Approx(1.0 / 3));
  CHECK(hit.s == doctest::Approx(0.5));
  CHECK(hit.t == doctest::Approx(0).epsilon(1e-9));
  CHECK(hit.d == doctest::Approx(0).epsilon(1e-9));
  EdgeProximity end;
  REQUIRE(edge_edge_proximity(x1[0], x1[1], x1[2], x1[3], end));
  CHECK(end.d == doctest::Approx(0.3));
  // The pair is sent back the way it came, within the plane: the edges' cross product (along y) is normal to
  // the approach, so the normal is the start gap, from Q's point (0.5, 0, 0.2) to P's (0.5, 0, 0): -z.
  Vec3 n = Vec3::Zero();
  REQUIRE(crossing_normal(x0, x1, t, hit, n));
  CHECK((n - Vec3(0, 0, -1)).norm() < 1e-12);
  // The same slide 0.5 m further along x passes P's end (x = 1) by 0.5: no hit.
  Vec3 y0[4] = {x0[0], x0[1], x0[2] + Vec3(1, 0, 0), x0[3] + Vec3(1, 0, 0)};
  Vec3 y1[4] = {x1[0], x1[1], x1[2] + Vec3(1, 0, 0), x1[3] + Vec3(1, 0, 0)};
  CHECK_FALSE(edge_edge_ccd(y0, y1, 0.01, t, hit));
}

TEST_CASE("edge-edge CCD in a common plane: both edges moving, and the plane tilted, meet at the hand-computed time") {
  // In the plane z = 0: P from (0,0,0) to (1,0,0) moving +y at 1 per step; Q from (0.4, 2, 0) to (0.6, 1, 0)
  // moving -y at 1 per step (a slanted edge). Q's lower end (y = 1 - t) meets P's line (y = t) at t = 1/2,
  // at x = 0.6 (s = 0.6 along P, u = 1 along Q). Then the whole configuration is rotated out of axis alignment
  // (a plane through the origin with normal (1, 2, 3) / |.|): the same hit.
  const Vec3 a0[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.4, 2, 0), Vec3(0.6, 1, 0)};
  Vec3 a1[4];
  for (int j = 0; j < 4; ++j) a1[j] = a0[j] + Vec3(0, j < 2 ? 1 : -1, 0);
  const Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(Vec3(0, 0, 1), Vec3(1, 2, 3)).toRotationMatrix();
  for (int tilted = 0; tilted < 2; ++tilted) {
    Vec3 x0[4], x1[4];
    for (int j = 0; j < 4; ++j) {
      x0[j] = tilted ? Vec3(r * a0[j]) : a0[j];
      x1[j] = tilted ? Vec3(r * a1[j]) : a1[j];
    }
    CHECK(coplanar_throughout(x0, x1));
    Real t = -1;
    EdgeProximity hit;
    REQUIRE(edge_edge_ccd(x0, x1, 1e-6, t, hit));
    CHECK(t == doctest::Approx(0.5));
    CHECK(hit.s == doctest::Approx(0.6));
    CHECK(hit.t == doctest::Approx(1));
  }
}

TEST_CASE("a vertex sliding within a triangle's plane: its cubic vanishes, and its edge meets the triangle's edge") {
  // Triangle a (0,0,0), b (1,0,0), c (0,1,0) in z = 0. Vertex v slides in that plane from (0.5, -0.5, 0) to
  // (0.5, 0.5, 0), entering the triangle across edge ab at t = 0.5; its edge to u = (0.5, -0.5, 0.3) leaves the
  // plane. The vertex-triangle cubic is zero for the whole step, so that test only sees the start, outside.
  const Vec3 x0[4] = {Vec3(0.5, -0.5, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const Vec3 x1[4] = {Vec3(0.5, 0.5, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  CHECK(coplanar_throughout(x0, x1));
  Real t = -1;
  TriangleProximity vt;
  CHECK_FALSE(vertex_triangle_ccd(x0, x1, 0.01, t, vt));
  // Edge vu against edge ab: the four points are coplanar when v is on ab's line (t = 0.5), where the edges touch
  // at v: s = 0 along vu, 0.5 along ab.
  const Vec3 u(0.5, -0.5, 0.3);
  const Vec3 e0[4] = {x0[0], u, x0[1], x0[2]}, e1[4] = {x1[0], u, x1[1], x1[2]};
  EdgeProximity hit;
  REQUIRE(edge_edge_ccd(e0, e1, 0.01, t, hit));
  CHECK(t == doctest::Approx(0.5));
  CHECK(hit.s == doctest::Approx(0).scale(1));
  CHECK(hit.t == doctest::Approx(0.5));
  CHECK(hit.d == doctest::Approx(0).scale(1));
}

TEST_CASE("edge-edge crossing: a near miss within the thickness is no crossing, edges that meet are") {
  // P from (-1, 0, -c) to (0, 0, 0) tilts its far end to (-1, 0, c) over the step; Q lies from (-0.5, g, 0) to
  // (0.5, g, 0). The lines are coplanar at t = 1/2 (P then along x, parallel to Q), g apart in y: they pass each
  // other g = 2 mm apart, never through, within a 10 mm thickness. The lines' cross product would send the pair
  // back along z by d = -c/2 = -5 cm, a gap that is not there; a near miss is left to the proximity passes.
  const Real c = 0.1, g = 0.002;
  const Vec3 x0[4] = {Vec3(-1, 0, -c), Vec3(0, 0, 0), Vec3(-0.5, g, 0), Vec3(0.5, g, 0)};
  const Vec3 x1[4] = {Vec3(-1, 0, c), Vec3(0, 0, 0), Vec3(-0.5, g, 0), Vec3(0.5, g, 0)};
  EdgeProximity px;
  Vec3 n = Vec3::Zero();
  Real d = 0;
  CHECK_FALSE(edge_edge_crossing(x0, x1, 0.01, px, n, d));
  // Edges that meet: Q upright at x = -0.5, from (-0.5, 1 mm, -0.5) to (-0.5, 1 mm, 0.5), moving to y = -1 mm,
  // while P stays in y = 0: they meet at t = 1/2 at (-0.5, 0, 0). P lay 1 mm on Q's -y side at the start, so
  // the pair goes back along -y (P x Q = (1, 0, 0) x (0, 0, 1) there), and it ends 1 mm across: d = -1 mm.
  const Vec3 y0[4] = {x0[0], x0[1], Vec3(-0.5, 0.001, -0.5), Vec3(-0.5, 0.001, 0.5)};
  const Vec3 y1[4] = {x1[0], x1[1], Vec3(-0.5, -0.001, -0.5), Vec3(-0.5, -0.001, 0.5)};
  REQUIRE(edge_edge_crossing(y0, y1, 0.01, px, n, d));
  CHECK(px.s == doctest::Approx(0.5));
  CHECK(px.t == doctest::Approx(0.5));
  CHECK((n - Vec3(0, -1, 0)).norm() < 1e-9);
  CHECK(d == doctest::Approx(-0.001));
}
