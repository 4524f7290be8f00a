// Stitches (systems/stitch_forces.h): force against its hand value and Jacobian against finite differences, a
// tube of two panels sewn round, and the same bytes at 1 and 2 threads.
#include <doctest/doctest.h>

#include <cmath>

#include "core/build_model.h"
#include "core/grid.h"
#include "systems/implicit_system.h"
#include "systems/integrate_implicit.h"
#include "systems/step.h"
#include "systems/stitch_forces.h"
#include "tests/support/scene_fixtures.h"
#include "tests/support/thread_bytes.h"

using namespace clothsim;

namespace {

// Two nx x ny panels of w x h m, one at y = +gap/2, the other at y = -gap/2, sewn along both side columns
// into a tube: each vertex of A to the vertex of B (weight 0), or with weight > 0 to the point that far along
// B's side edge to the next row (all rows but the last). No gravity.
BuiltScene sewn_tube(int nx, int ny, Real gap, Integrator integrator, Real sew_speed, Real timestep = 1e-3,
                     Real weight = 0) {
  SceneDesc s = test::stepped_scene(integrator, timestep);
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

// The step's matrix blocks of a lone stitch at (x, v) with its thread (rest, pull), in a workspace sized for it.
Workspace stitch_workspace(const Model& m, const std::vector<Vec3>& x, const std::vector<Vec3>& v, Real h, Real rest,
                           Real pull) {
  Workspace ws;
  ws.stitch_rest = {rest};
  ws.stitch_pull = {pull};
  ws.stitch_kx.assign(m.stitch_count, Sym3{});
  ws.stitch_block.assign(m.stitch_count, Sym3{});
  build_stitch_blocks(m, x, v, h, ws);
  return ws;
}

std::vector<Vec3> stitch_force_at(const Model& m, const std::vector<Vec3>& x, const std::vector<Vec3>& v, Real rest,
                                  Real pull) {
  std::vector<Vec3> f(3, Vec3::Zero());
  const std::vector<Real> r = {rest}, u = {pull};
  eval_stitches(m, x, v, r, u, f);
  return f;
}

}  // namespace

TEST_CASE("stitch force: a thread on the gap while sewing, its length clamped to sewSpeed h, Jacobian against differences") {
  // T = 0.5 s: at t = 0.2 the target is 0.6 |g0| long and shrinks at |g0| / 0.5 (sewSpeed 0.227 m/s); at
  // t = 0.6 the target is 0. The gap, closing at 0.1 m/s, is 0.02, 1 or 5 mm longer than the target; in a
  // step of 10 ms its thread may speed the closing to 0.1 + 2 h = 0.12 m/s (1.2 mm) while sewing, and to
  // sewSpeed past the schedule.
  for (Real w : {0.0, 0.3, 1.0})
    for (Real t : {0.2, 0.6})
      for (Real stretch : {2e-5, 1e-3, 5e-3}) {
        CAPTURE(w);
        CAPTURE(t);
        CAPTURE(stretch);
        Model m = one_stitch(w);
        const Real h = 0.01, g0 = m.stitch_gap0[0].norm();
        const Real length = t < 0.5 ? 0.6 * g0 : 0;
        CHECK(stitch_target_length(m, 0, t) == doctest::Approx(length).epsilon(1e-12));
        const Vec3 n = Vec3(2, -1, 2) / 3;
        std::vector<Vec3> x = {Vec3::Zero(), Vec3(0.0, 0.2, 0.1), Vec3(0.4, -0.1, 0.0)};
        x[0] = (1 - w) * x[1] + w * x[2] + (length + stretch) * n;
        std::vector<Vec3> v = {Vec3::Zero(), Vec3(-0.3, 0.0, 0.1), Vec3(0.1, 0.4, -0.2)};
        v[0] = (1 - w) * v[1] + w * v[2] - 0.1 * n + 0.05 * Vec3(1, 2, 0) / std::sqrt(5.0);  // n . g' = -0.1
        const Vec3 g = stitch_combine(m, 0, x), gd = stitch_combine(m, 0, v);
        CHECK(n.dot(gd) == doctest::Approx(-0.1).epsilon(1e-12));
        std::vector<Real> rest(1), pull(1);
        set_stitch_rest(m, x, v, t, h, rest, pull);
        // While sewing 1.2 mm; past the schedule sewSpeed h = 2.27 mm, no ramp.
        const Real reach = t < 0.5 ? std::min(0.12, std::sqrt(4 * g.norm())) * h : g0 / 0.5 * h;
        const Real expected_rest = stretch < reach ? length : g.norm() - reach;
        CHECK(rest[0] == doctest::Approx(expected_rest).epsilon(1e-12));
        CHECK(pull[0] == doctest::Approx((g.norm() - expected_rest) / h).epsilon(1e-9));
        if (t > 0.5 && stretch < 2e-3) CHECK(rest[0] == 0);  // sewn: the zero-length spring
        const std::vector<Vec3> f = stitch_force_at(m, x, v, rest[0], pull[0]);
        CHECK((f[0] + f[1] + f[2]).norm() < 1e-12);  // internal: no net force
        // Hand value: -(ke min(|g| - L*, reach) + kd (n . g' + pull)) n; -(ke g + kd g') once at rest 0.
        const Vec3 expected = rest[0] == 0 ? Vec3(-(300 * g + 0.7 * gd))
                                           : Vec3(-(300 * std::min(stretch, reach) + 0.7 * (n.dot(gd) + pull[0])) * n);
        CHECK((f[0] - expected).norm() < 1e-9 * expected.norm());
        CHECK((f[1] + (1 - w) * expected).norm() < 1e-9 * expected.norm());
        // A gap at its thread's length, shortening at its pull, in any direction, feels nothing; a shorter one is
        // slack, whatever its rate.
        if (t < 0.5) {
          std::vector<Vec3> xs = x, vs = v;
          const Vec3 along = 0.6 * g0 * Vec3(0, 0.6, 0.8);
          xs[0] = (1 - w) * x[1] + w * x[2] + (1 + 1e-9) * along;
          vs[0] = (1 - w) * v[1] + w * v[2] - 0.15 * along.normalized();
          for (const Vec3& fk : stitch_force_at(m, xs, vs, 0.6 * g0, 0.15)) CHECK(fk.norm() < 1e-6);
          xs[0] = (1 - w) * x[1] + w * x[2] + 0.5 * along;
          for (const Vec3& fk : stitch_force_at(m, xs, v, 0.6 * g0, 0.15)) CHECK(fk.norm() == 0);
        }
        // (A p)_i from the stitch = -h^2 (df/dx) p - h (df/dv) p by central differences at the step's rest
        // length; df/dx without damping, whose x-derivative the Jacobian drops (as for springs).
        Model stiff = m;
        stiff.stitch_kd = {0};
        const std::vector<Vec3> p = {Vec3(0.2, -0.7, 0.4), Vec3(-0.1, 0.3, 0.9), Vec3(0.6, 0.2, -0.5)};
        const Real eps = 1e-6;
        std::vector<Vec3> xp = x, xm = x, vp = v, vm = v;
        for (int k = 0; k < 3; ++k) xp[k] += eps * p[k], xm[k] -= eps * p[k], vp[k] += eps * p[k], vm[k] -= eps * p[k];
        const auto fxp = stitch_force_at(stiff, xp, v, rest[0], pull[0]), fxm = stitch_force_at(stiff, xm, v, rest[0], pull[0]);
        const auto fvp = stitch_force_at(m, x, vp, rest[0], pull[0]), fvm = stitch_force_at(m, x, vm, rest[0], pull[0]);
        const Workspace ws = stitch_workspace(m, x, v, h, rest[0], pull[0]);
        for (Index i = 0; i < 3; ++i) {
          const Vec3 dfdx_p = (fxp[i] - fxm[i]) / (2 * eps), dfdv_p = (fvp[i] - fvm[i]) / (2 * eps);
          CHECK((stitch_row(m, ws, i, p) - (-h * h * dfdx_p - h * dfdv_p)).norm() <= 1e-6 * stitch_row(m, ws, i, p).norm() + 1e-12);
          CHECK((stitch_dfdx_times(m, ws, i, p) - dfdx_p).norm() <= 1e-6 * dfdx_p.norm() + 1e-9);
          // The diagonal block is the row's response to p on particle i alone.
          for (int axis = 0; axis < 3; ++axis) {
            std::vector<Vec3> e(3, Vec3::Zero());
            e[i][axis] = 1;
            CHECK((stitch_row(m, ws, i, e) - stitch_diagonal(m, ws, i).full().col(axis)).norm() < 1e-12);
          }
        }
      }
}

TEST_CASE("a tube of two panels sewn round: the threads pull no faster than sewSpeed, then the gaps stay within 1 mm") {
  // 0.1 m apart at 0.2 m/s: the target reaches zero at 0.5 s; the threads, ramping up at 2 m/s^2, lag it by up
  // to 0.2^2 / (2 * 2) = 1 cm and close it by 0.55 s.
  const Real gap = 0.1, speed = 0.2;
  for (Integrator integrator : {Integrator::symplectic, Integrator::implicit}) {
    CAPTURE(int(integrator));
    BuiltScene b = sewn_tube(7, 5, gap, integrator, speed);
    const Model& m = b.model;
    REQUIRE(m.stitch_count == 10);
    CHECK(largest_gap(m, b.state.x) == doctest::Approx(gap));
    Workspace ws = make_workspace(m, b.options);
    State scratch = b.state;
    Real fastest = 0, smallest_allowed_margin = 1, fastest_closing = 0;
    for (int k = 0; k < 1000; ++k) {  // 1 s
      std::vector<Real> before(m.stitch_count);
      for (Index s = 0; s < m.stitch_count; ++s) before[s] = stitch_combine(m, s, b.state.x).norm();
      step(m, b.options, b.state, scratch, ws, b.options.dt);
      std::swap(b.state, scratch);
      const Real t = b.state.time;
      // How far a gap runs ahead of its target, |g| - (|g0| - speed t - tolerance), and how fast it closes.
      Real smallest = 1;
      for (Index s = 0; s < m.stitch_count; ++s) smallest = std::min(smallest, stitch_combine(m, s, b.state.x).norm());
      smallest_allowed_margin = std::min(smallest_allowed_margin, smallest - (std::max(0.0, gap - speed * t) - stitch_tolerance));
      for (const Vec3& v : b.state.v) fastest = std::max(fastest, v.norm());
      for (Index s = 0; s < m.stitch_count; ++s)
        fastest_closing = std::max(fastest_closing, (before[s] - stitch_combine(m, s, b.state.x).norm()) / b.options.dt);
      if (t >= 0.6) CHECK(largest_gap(m, b.state.x) <= 1e-3);
    }
    // A thread never pulls a gap shorter than its target, nor faster than sewSpeed: the implicit tube's gaps
    // never get ahead of the target and close at 0.203 m/s at most, no particle faster than 0.136 m/s. The
    // undamped symplectic panels coast and ring: their gaps run up to 26.5 mm ahead, particles at up to
    // 0.236 m/s.
    if (integrator == Integrator::implicit) {
      CHECK(smallest_allowed_margin >= -1e-12);
      CHECK(fastest_closing <= 1.05 * speed);
    }
    CHECK(fastest <= 1.25 * speed);
    CHECK(largest_gap(m, b.state.x) <= stitch_tolerance);
  }
}

TEST_CASE("sewing gives the same bytes at 1 and 2 threads") {
  // 2,400 particles: split over threads.
  test::check_same_bytes_at_1_and_2_threads(sewn_tube(40, 30, 0.1, Integrator::implicit, 0.2), 10);
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
