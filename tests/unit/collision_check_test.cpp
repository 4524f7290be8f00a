// The independent checks' mesh queries (systems/collision/mesh_check.h) against hand counts and against testing
// every triangle, written here again: the grids must change how fast the answer comes, never the answer.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/model.h"
#include "core/triangle_distance.h"
#include "systems/collision/collision_check.h"
#include "systems/collision/mesh_check.h"

using namespace clothsim;

namespace {

struct Mesh {
  std::vector<Vec3> v;
  std::vector<Index> t;
  void tri(Index a, Index b, Index c) { t.insert(t.end(), {a, b, c}); }
};

// A closed box, outward triangles.
void add_box(Mesh& m, const Vec3& lo, const Vec3& hi) {
  const Index o = Index(m.v.size());
  for (int k = 0; k < 8; ++k) m.v.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m.tri(o + f[0], o + f[1], o + f[2]);
    m.tri(o + f[0], o + f[2], o + f[3]);
  }
}

// A closed UV sphere: poles at center +- radius y, rings x segments quads between them.
void add_sphere(Mesh& m, const Vec3& center, Real radius, int rings, int segments) {
  const Real pi = std::acos(Real(-1));
  const Index o = Index(m.v.size());
  m.v.push_back(center + Vec3(0, radius, 0));
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const Real th = pi * r / rings, ph = 2 * pi * s / segments;
      m.v.push_back(center + radius * Vec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)));
    }
  const Index south = Index(m.v.size());
  m.v.push_back(center - Vec3(0, radius, 0));
  auto ring = [&](int r, int s) { return o + 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    m.tri(o, ring(1, s + 1), ring(1, s));
    m.tri(south, ring(rings - 1, s), ring(rings - 1, s + 1));
    for (int r = 1; r + 1 < rings; ++r) {
      m.tri(ring(r, s), ring(r, s + 1), ring(r + 1, s + 1));
      m.tri(ring(r, s), ring(r + 1, s + 1), ring(r + 1, s));
    }
  }
}

// splitmix64: the same points on every platform, unlike std's distributions.
struct Random {
  std::uint64_t s;
  Real uniform(Real a, Real b) {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return a + (b - a) * Real((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
  Vec3 point(Real a, Real b) { return Vec3(uniform(a, b), uniform(a, b), uniform(a, b)); }
};

// The brute force the grids replace, as collision_check.cpp wrote it before them.
Index brute_inside(const Vec3& p, const Mesh& m) {
  const Vec3 far = p + Vec3(0.5772, 0.6180, 0.5330).normalized() * 1e4;
  Index crossings = 0;
  for (std::size_t t = 0; t < m.t.size(); t += 3)
    crossings += segment_crosses_triangle(p, far, m.v[m.t[t]], m.v[m.t[t + 1]], m.v[m.t[t + 2]]);
  return crossings % 2;
}

Real brute_distance(const Vec3& p, const Mesh& m) {
  Real best = 1e300;
  for (std::size_t t = 0; t < m.t.size(); t += 3)
    best = std::min(best, point_triangle_distance(p, m.v[m.t[t]], m.v[m.t[t + 1]], m.v[m.t[t + 2]]));
  return best;
}

Index fast_inside(const Vec3& p, const Mesh& m) { return count_points_inside(std::span(&p, 1), m.v, m.t); }
Real fast_distance(const Vec3& p, const Mesh& m) { return min_point_distance(std::span(&p, 1), m.v, m.t); }

// A sphere of radius 1 in a box of side 4: box triangles far larger than the grids' cells.
Mesh nested_mesh() {
  Mesh m;
  add_sphere(m, Vec3(0, 0, 0), 1, 16, 32);
  add_box(m, Vec3(-2, -2, -2), Vec3(2, 2, 2));
  return m;
}

// Random points around the mesh, its own vertices, points far away and points on the cell borders of both grids
// (in the ray grid's plane at several depths along the ray).
std::vector<Vec3> probe_points(const Mesh& m) {
  std::vector<Vec3> pts;
  Random rng{7};
  for (int i = 0; i < 3000; ++i) pts.push_back(rng.point(-3, 3));
  pts.insert(pts.end(), m.v.begin(), m.v.end());
  for (const Real d : {10.0, 1e3, 1e6}) pts.push_back(Vec3(d, 0.3, -0.2));
  const BoxGrid<3> g3 = build_distance_grid(m.v, m.t);
  for (Index i = 0; i <= g3.n[0]; i += 3)
    for (Index j = 0; j <= g3.n[1]; j += 5)
      for (Index k = 0; k <= g3.n[2]; k += 7) pts.push_back(g3.lo + g3.h * Vec3(i, j, k));
  // The projection is linear: its rows are the images of the unit axes.
  Vec3 u, w;
  for (int k = 0; k < 3; ++k) {
    const Vec2 e = project_along_inside_ray(Vec3::Unit(k));
    u[k] = e[0];
    w[k] = e[1];
  }
  const BoxGrid<2> g2 = build_ray_grid(m.v, m.t);
  for (Index i = 0; i <= g2.n[0]; i += 2)
    for (Index j = 0; j <= g2.n[1]; j += 3)
      for (const Real s : {-1.0, 0.0, 0.7}) {
        const Vec2 c = g2.lo + g2.h * Vec2(i, j);
        pts.push_back(c[0] * u + c[1] * w + s * inside_ray_dir());
      }
  return pts;
}

}  // namespace

TEST_CASE("count_points_inside: lattice points in a unit box, a hand count") {
  Mesh box;
  add_box(box, Vec3(0, 0, 0), Vec3(1, 1, 1));
  std::vector<Vec3> pts;
  const Real c[] = {-0.75, -0.25, 0.25, 0.75, 1.25, 1.75};  // 0.25 and 0.75 inside
  for (Real x : c)
    for (Real y : c)
      for (Real z : c) pts.emplace_back(x, y, z);
  Index brute = 0;
  for (const Vec3& p : pts) brute += brute_inside(p, box);
  CHECK(brute == 8);
  CHECK(count_points_inside(pts, box.v, box.t) == 8);
}

TEST_CASE("count_points_inside: a sphere in a box, every probe point as testing every triangle") {
  const Mesh m = nested_mesh();
  const std::vector<Vec3> pts = probe_points(m);
  REQUIRE(build_ray_grid(m.v, m.t).n[0] > 8);  // the test needs a grid of many cells
  Index brute_total = 0, hand_checked = 0;
  for (const Vec3& p : pts) {
    const Index brute = brute_inside(p, m);
    brute_total += brute;
    CHECK(fast_inside(p, m) == brute);
    // Hand counts away from the surfaces: inside both (2 crossings), between them (1), outside the box (0).
    const Real r = p.norm(), edge = p.cwiseAbs().maxCoeff();
    if (r < 0.97 || edge > 2.01) {
      CHECK(brute == 0);
      ++hand_checked;
    }
    if (r > 1.01 && edge < 1.99) {
      CHECK(brute == 1);
      ++hand_checked;
    }
  }
  CHECK(hand_checked > 2500);
  CHECK(brute_total > 600);
  CHECK(count_points_inside(pts, m.v, m.t) == brute_total);
}

TEST_CASE("min_point_distance: a sphere in a box, every probe point as testing every triangle") {
  const Mesh m = nested_mesh();
  std::vector<Vec3> pts = probe_points(m);
  REQUIRE(build_distance_grid(m.v, m.t).n[0] > 8);
  Real brute_min = 1e300;
  for (const Vec3& p : pts) {
    const Real brute = brute_distance(p, m);
    brute_min = std::min(brute_min, brute);
    CHECK(fast_distance(p, m) == brute);
  }
  CHECK(brute_min == 0);  // the mesh's own vertices are among the points
  CHECK(min_point_distance(pts, m.v, m.t) == 0);
  // Without the vertices: a positive minimum, found in the first round or a later one.
  pts.resize(3000);
  brute_min = 1e300;
  for (const Vec3& p : pts) brute_min = std::min(brute_min, brute_distance(p, m));
  CHECK(brute_min > 0);
  CHECK(min_point_distance(pts, m.v, m.t) == brute_min);
  // Hand values: 1 m outside the box's face; 4 m above the sphere's pole, with the box removed.
  CHECK(fast_distance(Vec3(3, 0.5, -0.25), m) == 1);
  Mesh sphere;
  add_sphere(sphere, Vec3(0, 0, 0), 1, 16, 32);
  CHECK(fast_distance(Vec3(0, 5, 0), sphere) == 4);
  // Far clouds, where the rounds grow the radius many times before the first triangle is found.
  const std::vector<Vec3> far = {Vec3(40, 30, 20), Vec3(41, 30, 20), Vec3(-25, 60, 3)};
  CHECK(min_point_distance(far, m.v, m.t) == std::min({brute_distance(far[0], m), brute_distance(far[1], m),
                                                       brute_distance(far[2], m)}));
}

TEST_CASE("mesh queries: degenerate meshes and points") {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  Mesh one;  // a single triangle
  one.v = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  one.tri(0, 1, 2);
  CHECK(fast_distance(Vec3(0.25, 0.25, 2), one) == 2);
  CHECK(fast_inside(Vec3(0.1, 0.1, -1), one) == brute_inside(Vec3(0.1, 0.1, -1), one));
  Mesh points_only;  // triangles of zero size: boxes of zero size, every one at the same place or a few
  points_only.v = {Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(2, 1, 1)};
  points_only.tri(0, 0, 1);
  points_only.tri(2, 2, 2);
  CHECK(fast_distance(Vec3(1, 1, 4), points_only) == 3);
  CHECK(fast_inside(Vec3(0, 0, 0), points_only) == 0);
  Mesh empty;
  const std::vector<Vec3> some = {Vec3(0, 0, 0), Vec3(nan, 0, 0)};
  CHECK(min_point_distance(some, empty.v, empty.t) == 1e300);
  CHECK(count_points_inside(some, empty.v, empty.t) == 0);
  CHECK(min_point_distance({}, one.v, one.t) == 1e300);
  CHECK(count_points_inside({}, one.v, one.t) == 0);
  // A point that is not finite gives what the brute force gives: no crossing, no distance.
  const Mesh m = nested_mesh();
  CHECK(fast_inside(Vec3(nan, 0, 0), m) == brute_inside(Vec3(nan, 0, 0), m));
  CHECK(fast_distance(Vec3(nan, 0, 0), m) == brute_distance(Vec3(nan, 0, 0), m));
  // One huge triangle among the small ones: it fills many cells, the answers do not change.
  Mesh big = m;
  const Index o = Index(big.v.size());
  big.v.insert(big.v.end(), {Vec3(-10, -0.5, -10), Vec3(10, -0.5, -10), Vec3(0, -0.5, 15)});
  big.tri(o, o + 1, o + 2);
  Random rng{11};
  for (int i = 0; i < 200; ++i) {
    const Vec3 p = rng.point(-3, 3);
    CHECK(fast_inside(p, big) == brute_inside(p, big));
    CHECK(fast_distance(p, big) == brute_distance(p, big));
  }
}

TEST_CASE("mesh queries: the same answers at 1 and 4 threads") {
  const Mesh m = nested_mesh();
  const std::vector<Vec3> pts = probe_points(m);
  Index inside[2];
  Real nearest[2];
  for (int k = 0; k < 2; ++k) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, k == 0 ? 1 : 4);
    inside[k] = count_points_inside(pts, m.v, m.t);
    nearest[k] = min_point_distance(std::span(pts).first(3000), m.v, m.t);
  }
  CHECK(inside[0] == inside[1]);
  CHECK(nearest[0] == nearest[1]);
}

TEST_CASE("count_inside and min_collider_distance read a collider's own triangles") {
  // Two closed box colliders: the second's triangles and vertices follow the first's in the shared arrays.
  Mesh both;
  add_box(both, Vec3(0, 0, 0), Vec3(1, 1, 1));
  add_box(both, Vec3(3, 0, 0), Vec3(4, 2, 1));
  Model model;
  model.collision.colliders.resize(2);
  for (Index c = 0; c < 2; ++c) {
    ColliderInfo& ci = model.collision.colliders[c];
    ci.shape = ColliderShape::mesh;
    ci.closed = true;
    ci.vertex_begin = 8 * c;
    ci.vertex_end = 8 * c + 8;
    ci.tri_begin = 12 * c;
    ci.tri_end = 12 * c + 12;
  }
  model.collision.mesh_tri_index = both.t;
  CollisionScratch scratch;
  scratch.collider_x1 = both.v;
  const std::vector<Vec3> x = {Vec3(0.5, 0.5, 0.5), Vec3(3.5, 1.5, 0.5), Vec3(3.5, 0.5, 0.5), Vec3(2, 0.5, 0.5),
                               Vec3(9, 9, 9)};  // the last is beyond particle_count
  model.particle_count = 4;
  CHECK(count_inside(model, x, scratch, 0) == 1);
  CHECK(count_inside(model, x, scratch, 1) == 2);
  CHECK(min_collider_distance(model, x, scratch, 0) == 0.5);
  CHECK(min_collider_distance(model, x, scratch, 1) == 0.5);
  model.collision.colliders[1].closed = false;  // inside is not defined for an open mesh
  CHECK(count_inside(model, x, scratch, 1) == 0);
}

namespace {

// A cloth model of the mesh's triangles, with no collider: what count_intersecting_triangles reads. Stitches
// sew vertex pairs (both directions in the seam CSR, as build_seams makes it).
Model cloth_model(const Mesh& mesh, const std::vector<std::pair<Index, Index>>& stitches = {}) {
  Model m;
  m.particle_count = Index(mesh.v.size());
  m.tri_count = Index(mesh.t.size() / 3);
  m.tri_index = mesh.t;
  if (!stitches.empty()) {
    std::vector<std::vector<Index>> rows(m.particle_count);
    for (const auto& [a, b] : stitches) {
      rows[a].push_back(b);
      rows[b].push_back(a);
    }
    m.collision.seam_offset.assign(m.particle_count + 1, 0);
    for (Index i = 0; i < m.particle_count; ++i) {
      m.collision.seam_offset[i + 1] = m.collision.seam_offset[i] + Index(rows[i].size());
      m.collision.seam_index.insert(m.collision.seam_index.end(), rows[i].begin(), rows[i].end());
    }
  }
  return m;
}

// Every pair whose x ranges overlap, tested as the sweep along x did before the grid.
Index brute_intersecting(const Model& m, const std::vector<Vec3>& x) {
  Index hits = 0;
  for (Index a = 0; a < m.tri_count; ++a)
    for (Index b = a + 1; b < m.tri_count; ++b) {
      const Index *pa = &m.tri_index[3 * a], *pb = &m.tri_index[3 * b];
      auto xs = [&](const Index* p, bool high) {
        return high ? std::max({x[p[0]].x(), x[p[1]].x(), x[p[2]].x()}) : std::min({x[p[0]].x(), x[p[1]].x(), x[p[2]].x()});
      };
      if (xs(pb, false) > xs(pa, true) || xs(pa, false) > xs(pb, true)) continue;
      bool adjacent = false;
      for (int u = 0; u < 3; ++u)
        for (int w = 0; w < 3; ++w) adjacent = adjacent || m.collision.joined(pa[u], pb[w]);
      if (adjacent) continue;
      bool cross = false;
      for (int e = 0; e < 3; ++e)
        cross = cross || segment_crosses_triangle(x[pa[e]], x[pa[(e + 1) % 3]], x[pb[0]], x[pb[1]], x[pb[2]]) ||
                segment_crosses_triangle(x[pb[e]], x[pb[(e + 1) % 3]], x[pa[0]], x[pa[1]], x[pa[2]]);
      hits += cross;
    }
  return hits;
}

// `count` loose triangles, each within `spread` of a centre drawn in [lo, hi]^3.
void add_soup(Mesh& m, Random rng, int count, Real lo, Real hi, Real spread) {
  for (int k = 0; k < count; ++k) {
    const Vec3 c = rng.point(lo, hi);
    const Index o = Index(m.v.size());
    for (int i = 0; i < 3; ++i) m.v.push_back(c + rng.point(-spread, spread));
    m.tri(o, o + 1, o + 2);
  }
}

// An n x n sheet of quads from corner o along edges u and w.
void add_sheet(Mesh& m, const Vec3& o, const Vec3& u, const Vec3& w, int n) {
  const Index base = Index(m.v.size());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.v.push_back(o + u * (Real(i) / n) + w * (Real(j) / n));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Index a = base + j * (n + 1) + i;
      m.tri(a, a + 1, a + n + 2);
      m.tri(a, a + n + 2, a + n + 1);
    }
}

}  // namespace

TEST_CASE("count_intersecting_triangles: a hand count, and crossing sheets and a soup as testing every pair") {
  // One triangle piercing another: one pair; sewn at a corner, a seam, not counted.
  Mesh two;
  two.v = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.2, -0.5), Vec3(0.3, 0.2, 0.5), Vec3(0.2, 0.3, 0.5)};
  two.tri(0, 1, 2);
  two.tri(3, 4, 5);
  CHECK(count_intersecting_triangles(cloth_model(two), two.v) == 1);
  CHECK(count_intersecting_triangles(cloth_model(two, {{0, 3}}), two.v) == 0);
  // Two sheets crossing at right angles, a tilted third, and a soup of small random triangles over them.
  Mesh m;
  add_sheet(m, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), 12);
  add_sheet(m, Vec3(0.03, -0.5, 0.5123), Vec3(1, 0, 0), Vec3(0, 1, 0), 10);
  add_sheet(m, Vec3(-0.2, -0.3, -0.1), Vec3(1.1, 0.4, 0.2), Vec3(0.1, 0.3, 1.2), 9);
  add_soup(m, Random{3}, 300, -0.2, 1.2, 0.06);
  // Sew a few vertices of the first sheet to the second's, as a garment's seams.
  const Model model = cloth_model(m, {{5, 200}, {17, 201}, {40, 333}});
  const Index brute = brute_intersecting(model, m.v);
  CHECK(brute > 100);
  CHECK(count_intersecting_triangles(model, m.v) == brute);
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    CHECK(count_intersecting_triangles(model, m.v) == brute);
  }
}

TEST_CASE("count_collider_crossings: a cloth soup over an open collider sheet as testing every pair") {
  // The collider: an open sheet in y = 0.5 (22 x 22 quads), with one large triangle beside it.
  Mesh body;
  add_sheet(body, Vec3(0, 0.5, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), 22);
  const Index o = Index(body.v.size());
  body.v.insert(body.v.end(), {Vec3(1.2, -1, 0), Vec3(1.2, 2, 0), Vec3(1.2, 0.5, 3)});
  body.tri(o, o + 1, o + 2);
  Mesh cloth;
  // A thin triangle piercing the sheet inside one of its triangles: one pair.
  cloth.v = {Vec3(0.51, 0.3, 0.52), Vec3(0.52, 0.3, 0.52), Vec3(0.515, 0.7, 0.525)};
  cloth.tri(0, 1, 2);
  add_soup(cloth, Random{5}, 400, -0.1, 1.4, 0.08);
  Model model = cloth_model(cloth);
  ColliderInfo ci;
  ci.shape = ColliderShape::mesh;
  ci.closed = false;
  ci.tri_end = Index(body.t.size() / 3);
  ci.vertex_end = Index(body.v.size());
  model.collision.colliders = {ci};
  model.collision.mesh_tri_index = body.t;
  CollisionScratch scratch;
  scratch.collider_x1 = body.v;
  Index brute = 0;
  for (std::size_t t = 0; t < cloth.t.size(); t += 3) {
    const Vec3 &p0 = cloth.v[cloth.t[t]], &p1 = cloth.v[cloth.t[t + 1]], &p2 = cloth.v[cloth.t[t + 2]];
    for (std::size_t k = 0; k < body.t.size(); k += 3) {
      const Vec3 &a = body.v[body.t[k]], &b = body.v[body.t[k + 1]], &c = body.v[body.t[k + 2]];
      const Vec3 p[3] = {p0, p1, p2}, q[3] = {a, b, c};
      bool cross = false;
      for (int e = 0; e < 3; ++e)
        cross = cross || segment_crosses_triangle(p[e], p[(e + 1) % 3], a, b, c) ||
                segment_crosses_triangle(q[e], q[(e + 1) % 3], p0, p1, p2);
      brute += cross;
    }
    if (t == 0) CHECK(brute == 1);
  }
  CHECK(brute > 30);
  CHECK(count_collider_crossings(model, cloth.v, scratch, 0) == brute);
}
