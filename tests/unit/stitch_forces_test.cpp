// Stitches (systems/stitch_forces.h): force and Jacobian against finite differences, a tube of two panels sewn
// round, and the same bytes at 1 and 2 threads.
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "core/build_model.h"
#include "core/grid.h"
#include "systems/implicit_system.h"
#include "systems/integrate_implicit.h"
#include "systems/step.h"
#include "systems/stitch_forces.h"

using namespace clothsim;

namespace {

// Two nx x ny panels of w x h m, one at y = +gap/2, the other at y = -gap/2, sewn along both side columns
// into a tube: each vertex of A to the vertex of B (weight 0), or with weight > 0 to the point that far along
// B's side edge to the next row (all rows but the last). No gravity.
BuiltScene sewn_tube(int nx, int ny, Real gap, Integrator integrator, Real sew_speed, Real timestep = 1e-3,
                     Real weight = 0) {
  SceneDesc s;
  s.path = "<test>";
  s.simulation.integrator = integrator;
  s.simulation.timestep = timestep;
  s.simulation.fps = 1.0 / timestep;
  s.simulation.gravity = Vec3::Zero();
  ClothDesc c;
  c.name = "tube";
  c.obj = "<generated>";
  c.sew_speed = sew_speed;
  // Light panels (0.06 m^2, about 4e-4 kg a vertex): soft and lightly damped, so the symplectic step at 1 ms is
  // stable (h omega about 0.5, h kd / m about 0.1).
  c.density = 1;
  c.stiffness = 10;
  c.damping = 0.005;
  s.cloths.push_back(c);
  MeshData a = make_grid_mesh(nx, ny, 0.3, 0.2), mesh;
  const Index n = a.vertex_count();
  for (int side = 0; side < 2; ++side) {
    const Index base = mesh.vertex_count();
    for (Vec3 p : a.positions) mesh.positions.push_back(p + Vec3(0, side ? -gap / 2 : gap / 2, 0));
    for (Index t : a.tri_index) mesh.tri_index.push_back(base + t);
  }
  for (int j = 0; j < (weight > 0 ? ny - 1 : ny); ++j)
    for (int i : {0, nx - 1}) {
      const Index v = j * nx + i;
      mesh.stitch_a.push_back(v);
      mesh.stitch_b.push_back(n + v);
      mesh.stitch_c.push_back(weight > 0 ? n + v + nx : n + v);
      mesh.stitch_w.push_back(weight);
    }
  return build_model(s, std::vector<MeshData>{mesh});
}

Real largest_gap(const Model& m, const std::vector<Vec3>& x) {
  Real g = 0;
  for (Index s = 0; s < m.stitch_count; ++s) g = std::max(g, stitch_combine(m, s, x).norm());
  return g;
}

// One stitch over three free particles, with stiffness, damping and a sewing target.
Model one_stitch(Real w) {
  Model m;
  m.particle_count = 3;
  m.particle_inv_mass = {1.0, 0.5, 2.0};
  m.stitch_count = 1;
  m.stitch_a = {0};
  m.stitch_b = {1};
  m.stitch_c = {2};
  m.stitch_w = {w};
  m.stitch_ke = {300};
  m.stitch_kd = {0.7};
  m.stitch_gap0 = {Vec3(0.1, -0.05, 0.02)};
  m.stitch_close_time = {0.5};
  m.particle_stitch_offset = {0, 1, 2, 3};
  m.particle_stitch_index = {0, 1, 2};
  return m;
}

}  // namespace

TEST_CASE("stitch force: zero at the target gap, sums to zero, and its Jacobian matches finite differences") {
  for (Real w : {0.0, 0.3, 1.0}) {
    CAPTURE(w);
    const Model m = one_stitch(w);
    const Real t = 0.2, h = 0.01;
    std::vector<Vec3> x = {Vec3(0.3, 0.1, -0.2), Vec3(0.0, 0.2, 0.1), Vec3(0.4, -0.1, 0.0)};
    std::vector<Vec3> v = {Vec3(0.5, -0.1, 0.2), Vec3(-0.3, 0.0, 0.1), Vec3(0.1, 0.4, -0.2)};
    auto force = [&](const std::vector<Vec3>& xx, const std::vector<Vec3>& vv) {
      std::vector<Vec3> f(3, Vec3::Zero());
      eval_stitches(m, xx, vv, t, f);
      return f;
    };
    const std::vector<Vec3> f = force(x, v);
    CHECK((f[0] + f[1] + f[2]).norm() < 1e-12);  // internal: no net force
    // At g = g*(t) and g' = g*'(t) the force vanishes: target at t = 0.2 of T = 0.5 is 0.6 g0.
    std::vector<Vec3> xs = x, vs = v;
    xs[0] = (1 - w) * x[1] + w * x[2] + 0.6 * m.stitch_gap0[0];
    vs[0] = (1 - w) * v[1] + w * v[2] - m.stitch_gap0[0] / 0.5;
    for (const Vec3& fk : force(xs, vs)) CHECK(fk.norm() < 1e-12);
    // (A p)_i from the stitch = -h^2 (df/dx) p - h (df/dv) p, central differences exact for a linear force.
    const std::vector<Vec3> p = {Vec3(0.2, -0.7, 0.4), Vec3(-0.1, 0.3, 0.9), Vec3(0.6, 0.2, -0.5)};
    const Real eps = 1e-4;
    std::vector<Vec3> xp = x, xm = x, vp = v, vm = v;
    for (int k = 0; k < 3; ++k) xp[k] += eps * p[k], xm[k] -= eps * p[k], vp[k] += eps * p[k], vm[k] -= eps * p[k];
    const auto fxp = force(xp, v), fxm = force(xm, v), fvp = force(x, vp), fvm = force(x, vm);
    for (Index i = 0; i < 3; ++i) {
      const Vec3 dfdx_p = (fxp[i] - fxm[i]) / (2 * eps), dfdv_p = (fvp[i] - fvm[i]) / (2 * eps);
      CHECK((stitch_row(m, i, h, p) - (-h * h * dfdx_p - h * dfdv_p)).norm() < 1e-9);
      CHECK((stitch_dfdx_times(m, i, p) - dfdx_p).norm() < 1e-7);
      // The diagonal coefficient is the row's response to p on particle i alone.
      std::vector<Vec3> e(3, Vec3::Zero());
      e[i] = Vec3(1, 0, 0);
      CHECK(stitch_row(m, i, h, e).x() == doctest::Approx(stitch_diagonal(m, i, h)).epsilon(1e-12));
    }
  }
}

TEST_CASE("a tube of two panels sewn round: the gap closes no faster than sewSpeed, then stays within 1 mm") {
  // 0.1 m apart at 0.2 m/s: the target reaches zero at 0.5 s.
  const Real gap = 0.1, speed = 0.2;
  for (Integrator integrator : {Integrator::symplectic, Integrator::implicit}) {
    CAPTURE(int(integrator));
    BuiltScene b = sewn_tube(7, 5, gap, integrator, speed);
    const Model& m = b.model;
    REQUIRE(m.stitch_count == 10);
    CHECK(largest_gap(m, b.state.x) == doctest::Approx(gap));
    Workspace ws = make_workspace(m, b.options);
    State scratch = b.state;
    Real fastest = 0, smallest_allowed_margin = 1;
    for (int k = 0; k < 1000; ++k) {  // 1 s
      step(m, b.options, b.state, scratch, ws, b.options.dt);
      std::swap(b.state, scratch);
      const Real t = b.state.time;
      // No gap closes ahead of the target: |g| >= |g0| - speed t - tolerance.
      Real smallest = 1;
      for (Index s = 0; s < m.stitch_count; ++s) smallest = std::min(smallest, stitch_combine(m, s, b.state.x).norm());
      smallest_allowed_margin = std::min(smallest_allowed_margin, smallest - (std::max(0.0, gap - speed * t) - stitch_tolerance));
      for (const Vec3& v : b.state.v) fastest = std::max(fastest, v.norm());
      if (t >= 0.5) CHECK(largest_gap(m, b.state.x) <= 1e-3);
    }
    CHECK(smallest_allowed_margin >= -1e-12);
    CHECK(largest_gap(m, b.state.x) <= stitch_tolerance);
    // Each side moves at about half the closing speed; nothing flies off.
    CHECK(fastest < 4 * speed);
  }
}

TEST_CASE("sewing gives the same bytes at 1 and 2 threads") {
  std::vector<State> results;
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    BuiltScene b = sewn_tube(40, 30, 0.1, Integrator::implicit, 0.2);  // 2,400 particles: split over threads
    Workspace ws = make_workspace(b.model, b.options);
    State scratch = b.state;
    for (int k = 0; k < 10; ++k) {
      step(b.model, b.options, b.state, scratch, ws, b.options.dt);
      std::swap(b.state, scratch);
    }
    results.push_back(b.state);
  }
  CHECK(std::memcmp(results[1].x.data(), results[0].x.data(), results[0].x.size() * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(results[1].v.data(), results[0].v.data(), results[0].v.size() * sizeof(Vec3)) == 0);
}

TEST_CASE("the Cholesky preconditioner factors the stitches: a fresh factor solves a sewn step in one iteration") {
  // A factor without the stitches' terms is not the step's matrix: CG then needs more than one iteration (on
  // the knife-pleat dress it stalled at a residual of 1.2).
  for (Real weight : {0.0, 0.25}) {
    CAPTURE(weight);
    BuiltScene b = sewn_tube(7, 5, 0.1, Integrator::implicit, 0.2, 1e-2, weight);
    REQUIRE(b.model.stitch_count == (weight > 0 ? 8 : 10));
    b.options.solver.preconditioner = Preconditioner::cholesky;
    b.options.solver.cg_tolerance = 1e-9;
    Workspace ws = make_workspace(b.model, b.options);
    State out = b.state;
    const StepResult r = integrate_implicit(b.model, b.options.solver, b.state, out, ws, b.options.dt);
    CHECK(r.solve.factorizations == 1);
    CHECK(r.solve.cg_iterations == 1);
    CHECK(r.solve.cg_residual < 1e-9);
  }
}
