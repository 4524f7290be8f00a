#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "core/csr.h"
#include "core/spring_colours.h"
#include "core/tethers.h"
#include "systems/collision/collide.h"
#include "systems/diagnostics.h"
#include "systems/displace.h"
#include "systems/integrate_implicit.h"
#include "systems/spring_forces.h"
#include "systems/strain_limit.h"
#include "tests/support/spring_fixtures.h"

using namespace clothsim;
using namespace clothsim::test;

namespace {

// A soft sheet hanging from its two top corners: without a limit its springs near the pins stretch far.
GridSpec soft_sheet(Real max_strain, Integrator integrator) {
  GridSpec g;
  g.nx = g.ny = 12;
  g.stiffness = 4;
  g.damping = 0.02;
  g.pins = {0, 11};
  g.max_strain = max_strain;
  g.integrator = integrator;
  return g;
}

// Largest strain seen after any step over `steps` steps of h.
Real worst_strain(const GridSpec& g, Real h, int steps, bool check_velocity = false) {
  BuiltScene s = grid_sheet(g);
  Workspace ws = make_workspace(s.model, s.options);
  State scratch = s.state;
  Real worst = 0;
  for (int k = 0; k < steps; ++k) {
    step(s.model, s.options, s.state, scratch, ws, h);
    if (check_velocity) {
      // The correction moved positions and velocities together: x' = x + h v' still holds.
      Real mismatch = 0;
      for (Index i = 0; i < s.model.particle_count; ++i)
        mismatch = std::max(mismatch, (scratch.x[i] - s.state.x[i] - h * scratch.v[i]).norm());
      REQUIRE(mismatch < 1e-12);
    }
    std::swap(s.state, scratch);
    REQUIRE(state_is_finite(s.state));
    worst = std::max(worst, max_spring_strain(s.model, s.state.x));
  }
  return worst;
}

// A chain of n springs of rest length 1 along x, particle 0 pinned when `pinned`, unit masses, stretched to
// `length` a spring; one cloth, so build_tethers ties it to its pin (its path over the springs is the straight
// line). Built by hand: build_model lumps mass from triangles, and a chain has none.
BuiltScene chain(int n, Real length, Real max_strain, bool pinned) {
  BuiltScene b;
  Model& m = b.model;
  m.particle_count = n + 1;
  m.particle_inv_mass.assign(n + 1, 1.0);
  if (pinned) {
    m.particle_inv_mass[0] = 0;
    m.pinned = {0};
  }
  m.spring_count = n;
  std::vector<Vec3> x;
  for (Index i = 0; i <= n; ++i) x.push_back(Vec3(length * i, 0, 0));
  for (Index s = 0; s < n; ++s) {
    m.spring_a.push_back(s);
    m.spring_b.push_back(s + 1);
    m.spring_rest.push_back(1.0);
  }
  m.spring_max_strain = ParamField(max_strain);
  m.strain_limited = true;
  ClothInfo cloth;
  cloth.particle_end = n + 1;
  cloth.spring_end = n;
  m.cloths.push_back(cloth);
  build_spring_colours(m);
  const std::vector<char> straight_rest = {0};
  build_tethers(m, std::vector<Vec3>(x.begin(), x.end()), straight_rest);
  b.state = make_state(m, x);
  return b;
}

// The limit this one replaced (docs/stability.md): Jacobi sweeps, each particle moving by the average of its
// over-stretched springs' proposals, with the same stopping rule and cap. Kept here as the yardstick.
int jacobi_strain_limit(const Model& m, State& out, Real h) {
  std::vector<Index> offset, index;
  build_particle_springs(m, offset, index);
  std::vector<Vec3> corr(m.spring_count);
  int it = 0;
  for (; it < strain_limit_max_iterations; ++it) {
    Real worst = -1;
    for (Index s = 0; s < m.spring_count; ++s) {
      const Index a = m.spring_a[s], b = m.spring_b[s];
      const Vec3 d = out.x[b] - out.x[a];
      const Real len = d.norm(), rest = m.spring_rest[s], limit = m.spring_max_strain[s];
      const Real excess = (len - rest) / rest - limit, w = m.particle_inv_mass[a] + m.particle_inv_mass[b];
      worst = std::max(worst, excess);
      corr[s] = excess > 0 && w > 0 ? Vec3((len - (1 + limit) * rest) / (w * len) * d) : Vec3::Zero();
    }
    if (worst <= 0.5 * strain_limit_tolerance) break;
    for (Index i = 0; i < m.particle_count; ++i) {
      Vec3 sum = Vec3::Zero();
      int active = 0;
      for (Index k = offset[i]; k < offset[i + 1]; ++k) {
        const Index e = index[k];
        const Vec3& c = corr[e >= 0 ? e : ~e];
        if (c.isZero(0)) continue;
        sum += e >= 0 ? c : Vec3(-c);
        ++active;
      }
      if (active == 0 || !(m.particle_inv_mass[i] > 0)) continue;
      const Vec3 dx = (m.particle_inv_mass[i] / active) * sum;
      out.x[i] += dx;
      out.v[i] += dx / h;
    }
  }
  return it;
}

// The peer sheet of docs/performance.md at 64 x 64: 1 m, 1 kg, 10000 N/m springs, held by the two corners of
// one edge and dropped from flat, implicit at 1/24 s with CG tolerance 1e-2: the first step is a free fall
// (springs at rest have no stiffness across themselves), so the limit must build the drape around the pins.
BuiltScene dropped_sheet(int n) {
  SceneDesc scene = grid_scene(n, n, 1.0, Integrator::implicit, 1.0 / 24);
  scene.simulation.gravity = Vec3(0, -9.81, 0);
  scene.simulation.cg_tolerance = 1e-2;
  ClothDesc& c = scene.cloths[0];
  c.stiffness = 10000;
  c.bend_scale = 0.1;
  c.damping = 0.1;
  c.density = 1;
  c.max_strain = 0.095;
  c.pins = {0, Index(n - 1)};
  return build(scene);
}

struct LimitComparison {
  int sweeps = 0, most = 0;                          // this limit: total and largest in one step
  int jacobi_sweeps = 0, jacobi_most = 0, jacobi_capped = 0;
  Real jacobi_worst = 0;                             // largest strain the Jacobi sweeps left
};

// Runs `steps` implicit steps of h (the model's step when 0); each step's integrated state goes to both limits:
// the Jacobi yardstick on a copy, this limit on the state the run continues from. Checks after every step that
// every spring is within tau + strain_limit_tolerance and that velocities moved with positions. Counts are
// deterministic, so the tests assert them, never times.
LimitComparison compare_with_jacobi(BuiltScene s, int steps, Real tau, Real h = 0) {
  const Model& m = s.model;
  if (h == 0) h = s.options.dt;
  Workspace ws = make_workspace(m, s.options);
  State out = s.state;
  LimitComparison r;
  for (int k = 0; k < steps; ++k) {
    integrate_implicit(m, s.options.solver, s.state, out, ws, h);
    State jacobi = out;
    const int j = jacobi_strain_limit(m, jacobi, h);
    r.jacobi_sweeps += j;
    r.jacobi_most = std::max(r.jacobi_most, j);
    r.jacobi_capped += j == strain_limit_max_iterations;
    r.jacobi_worst = std::max(r.jacobi_worst, max_spring_strain(m, jacobi.x));
    const State before = out;
    const int it = apply_strain_limit(m, out, h);
    r.sweeps += it;
    r.most = std::max(r.most, it);
    CHECK(it < strain_limit_max_iterations);
    CHECK(max_spring_strain(m, out.x) <= tau + strain_limit_tolerance);
    Real mismatch = 0;  // x' - x = h (v' - v) for the correction
    for (Index i = 0; i < m.particle_count; ++i)
      mismatch = std::max(mismatch, ((out.x[i] - before.x[i]) - h * (out.v[i] - before.v[i])).norm());
    CHECK(mismatch < 1e-12);
    REQUIRE(state_is_finite(out));
    std::swap(s.state, out);
  }
  return r;
}

}  // namespace

TEST_CASE("strain limiting keeps every spring within maxStrain + the documented tolerance") {
  const Real h = 1.0 / 240;
  const int steps = 480;  // two seconds
  const Real free_strain = worst_strain(soft_sheet(0, Integrator::implicit), h, steps);
  MESSAGE("largest strain without a limit " << free_strain);
  CHECK(free_strain > 0.3);
  for (Integrator integ : {Integrator::implicit, Integrator::symplectic}) {
    const Real limited = worst_strain(soft_sheet(0.1, integ), h, steps, true);
    MESSAGE("integrator " << int(integ) << ": largest strain with maxStrain 0.1: " << limited);
    CHECK(limited <= 0.1 + strain_limit_tolerance);
    CHECK(limited > 0.09);  // the limit is active, not a sheet that never stretched
  }
}

TEST_CASE("strain limit on one spring: a pinned end stays, the free end moves back to the limit") {
  BuiltScene s = two_particle_spring(0, 1, 10, 0, 1, 1.5, Integrator::symplectic);
  s.model.strain_limited = true;
  s.model.spring_max_strain = ParamField(0.2);
  build_spring_colours(s.model);  // no cloth, so no tether: the sweep does it
  const int it = apply_strain_limit(s.model, s.state, 0.1);
  CHECK(it == 1);  // one spring: the first sweep projects exactly (no over-relaxation)
  CHECK(s.state.x[0] == Vec3(0, 0, 0));
  CHECK(s.state.x[1].x() == doctest::Approx(1.2));
  CHECK(s.state.v[1].x() == doctest::Approx(-3.0));  // moved by -0.3 m over h = 0.1 s
  CHECK(max_spring_strain(s.model, s.state.x) == doctest::Approx(0.2));
}

TEST_CASE("a chain pinned at one end and stretched: the tethers alone give the projection, x_i = i (1 + tau) rest") {
  // Every spring 1.5 long for maxStrain 0.2: the nearest configuration (equal masses) within the limit puts
  // particle i at 1.2 i, each moving back by 0.3 i (spring i's KKT multiplier is the sum of the moves beyond it,
  // 0.3 (i + ... + n) > 0, so every spring ends exactly at its limit). Each tether is 1.2 i long: one projection
  // each lands the particle there.
  const int n = 6;
  const Real h = 0.1;
  BuiltScene s = chain(n, 1.5, 0.2, true);
  REQUIRE(s.model.tether_particle.size() == std::size_t(n));
  CHECK(s.model.tether_length[n - 1] == doctest::Approx(1.2 * n));
  CHECK(s.model.spring_colour_offset.size() == 3);  // a chain takes two colours
  const int it = apply_strain_limit(s.model, s.state, h);
  CHECK(it == 0);  // no sweep: the tethers left every spring at its limit
  for (Index i = 0; i <= n; ++i) {
    CHECK(s.state.x[i].x() == doctest::Approx(1.2 * i));
    CHECK(s.state.v[i].x() == doctest::Approx(-0.3 * i / h));
  }
  CHECK(max_spring_strain(s.model, s.state.x) == doctest::Approx(0.2));
}

TEST_CASE("a free spring is projected in one sweep, each end half way, a free chain keeps its momentum") {
  // Two equal masses 1.5 apart, limit 1.2: each end moves 0.15 towards the other (Provot's split by inverse mass).
  BuiltScene one = chain(1, 1.5, 0.2, false);
  CHECK(one.model.tether_particle.empty());  // no pin, no tether
  CHECK(apply_strain_limit(one.model, one.state, 0.1) == 1);
  CHECK(one.state.x[0].x() == doctest::Approx(0.15));
  CHECK(one.state.x[1].x() == doctest::Approx(1.35));

  // Eight springs, each 1.5 for a limit of 1.2: equal and opposite moves at every projection, so the centre of
  // mass and the momentum (velocities start at zero) stay where they were, to round-off.
  const int n = 8;
  BuiltScene s = chain(n, 1.5, 0.2, false);
  const int it = apply_strain_limit(s.model, s.state, 0.1);
  MESSAGE("free chain of " << n << " springs: " << it << " sweeps");
  CHECK(it > 1);
  CHECK(it < 50);
  Vec3 centre = Vec3::Zero(), momentum = Vec3::Zero();
  for (Index i = 0; i <= n; ++i) {
    centre += s.state.x[i] / (n + 1);
    momentum += s.state.v[i];
  }
  CHECK(centre.x() == doctest::Approx(1.5 * n / 2).epsilon(1e-12));
  CHECK(momentum.norm() < 1e-9);
  CHECK(max_spring_strain(s.model, s.state.x) <= 0.2 + strain_limit_tolerance);
}

TEST_CASE("a 64 x 64 sheet dropped from flat at 1/24 s: every step within the limit, in a tenth of Jacobi's sweeps") {
  // The drop is over by step 6 (later steps need no sweep); the first eight steps hold all the work.
  const LimitComparison r = compare_with_jacobi(dropped_sheet(64), 8, 0.095);
  MESSAGE("8 steps: " << r.sweeps << " sweeps (most in one step " << r.most << "); Jacobi on the same states "
                      << r.jacobi_sweeps << " (most " << r.jacobi_most << ")");
  CHECK(r.sweeps <= 40);
  CHECK(10 * r.sweeps < r.jacobi_sweeps);
}

TEST_CASE("a soft 32 x 32 sheet hanging by two corners: Jacobi hits its cap, this limit converges in an eighth") {
  // 4 N/m springs would stretch 440% (docs/stability.md): the limit holds the whole sheet up at every step, a
  // sheet-wide correction the Jacobi sweeps cannot carry within their cap.
  GridSpec g = soft_sheet(0.1, Integrator::implicit);
  g.nx = g.ny = 32;
  g.pins = {0, 31};
  const LimitComparison r = compare_with_jacobi(grid_sheet(g), 48, 0.1, 1.0 / 240);
  MESSAGE("48 steps: " << r.sweeps << " sweeps (most in one step " << r.most << "); Jacobi on the same states "
                       << r.jacobi_sweeps << ", capped in " << r.jacobi_capped << " steps, largest strain "
                       << r.jacobi_worst);
  CHECK(r.jacobi_capped >= 10);
  CHECK(r.jacobi_worst > 0.1 + strain_limit_tolerance);
  CHECK(r.most < strain_limit_max_iterations / 4);
  CHECK(8 * r.sweeps < r.jacobi_sweeps);
}

TEST_CASE("the strain limit gives the same bytes at 1, 2 and 3 threads") {
  // A 64 x 64 sheet's colours hold about 1,800 springs each and its 4,094 tethers span two particle blocks, so
  // both passes split at two and three threads.
  std::vector<State> results;
  for (int threads : {1, 2, 3}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    BuiltScene s = dropped_sheet(64);
    Workspace ws = make_workspace(s.model, s.options);
    CHECK(run_steps(s.model, s.options, s.state, ws, s.options.dt, 6).strain_sweeps > 6);
    results.push_back(s.state);
  }
  for (int t = 1; t < 3; ++t) {
    CHECK(std::memcmp(results[t].x.data(), results[0].x.data(), results[0].x.size() * sizeof(Vec3)) == 0);
    CHECK(std::memcmp(results[t].v.data(), results[0].v.data(), results[0].v.size() * sizeof(Vec3)) == 0);
  }
}

TEST_CASE("a limit the chain cannot meet stops at the sweep cap and is reported unmet") {
  // Two springs of rest 1 between pins 3 m apart: with maxStrain 0.2 they can span 2.4 m at most, so every sweep
  // moves the middle particle between its two limits and none ends within both.
  BuiltScene s = chain(2, 1.5, 0.2, true);
  s.model.particle_inv_mass[2] = 0;
  s.model.pinned = {0, 2};
  build_tethers(s.model, s.state.x, std::vector<char>{0});
  CHECK_FALSE(strain_limit_met(s.model, s.state.x));
  CHECK(apply_strain_limit(s.model, s.state, 0.1) == strain_limit_max_iterations);
  CHECK_FALSE(strain_limit_met(s.model, s.state.x));
  // The same chain with a free end meets it (the tethers alone do it).
  BuiltScene ok = chain(2, 1.5, 0.2, true);
  CHECK(apply_strain_limit(ok.model, ok.state, 0.1) < strain_limit_max_iterations);
  CHECK(strain_limit_met(ok.model, ok.state.x));
}

TEST_CASE("after the collide stage a contact stays in front of its plane and its neighbours come to it") {
  // A free chain of two springs (rest 1, maxStrain 0.1) with its middle particle lifted 0.5 off the line, as a
  // contact push leaves it: both springs 11.8 % long. Held on its plane y >= 0.5 (contact normal +y), the middle
  // stays there and the ends come up to it; the plain limit pulls the middle back down instead.
  BuiltScene b = chain(2, 1.0, 0.1, false);
  b.state.x[1].y() = 0.5;
  const Real h = 0.01;
  State plain = b.state;
  apply_strain_limit(b.model, plain, h);
  CHECK(plain.x[1].y() < 0.49);

  State held = b.state;
  held.contact.assign(3, ContactHold{});
  held.contact[1].normal = Vec3(0, 1, 0);
  std::vector<Real> offset(3);
  set_contact_planes(b.model, held, offset);
  const int sweeps = apply_strain_limit_on_contacts(b.model, held, h, offset);
  CHECK(sweeps > 0);
  CHECK(sweeps < strain_limit_max_iterations);
  CHECK(offset[1] == 0.5);
  CHECK(held.x[1].y() >= 0.5);
  CHECK(held.x[1].y() == doctest::Approx(0.5).epsilon(1e-12));
  // Each end comes up its spring to the limit's 1.1: 0.018 along a spring of slope 0.5, about 0.008 in y.
  CHECK(held.x[0].y() > 0.007);
  CHECK(held.x[2].y() > 0.007);
  CHECK(max_spring_strain(b.model, held.x) <= 0.1 + strain_limit_tolerance);
  for (Index i = 0; i < 3; ++i)  // velocities moved with positions: x' = x + h v' still holds
    CHECK((held.x[i] - b.state.x[i] - h * (held.v[i] - b.state.v[i])).norm() < 1e-12);
}

TEST_CASE("a contact moved behind its plane after the planes were set goes back onto it, with no sweep") {
  // What the stitch pass may do between the rounds after the collide stage: the springs are within their limit,
  // so only the plane acts.
  BuiltScene b = chain(2, 1.0, 0.1, false);
  b.state.contact.assign(3, ContactHold{});
  b.state.contact[1].normal = Vec3(0, 1, 0);
  std::vector<Real> offset(3);
  set_contact_planes(b.model, b.state, offset);
  b.state.x[1].y() = -0.01;
  CHECK(apply_strain_limit_on_contacts(b.model, b.state, 0.01, offset) == 0);
  CHECK(b.state.x[1].y() == 0);
  CHECK(b.state.v[1].y() == doctest::Approx(1.0).epsilon(1e-12));  // 0.01 m in a 0.01 s step
}

TEST_CASE("a spring whose two ends are held apart by their contacts stops at the sweep cap, unmet") {
  // A pinch: particle 0 may only move in -x, particle 1 only in +x, and their spring is 20 % long.
  BuiltScene b = chain(1, 1.2, 0.1, false);
  b.state.contact.assign(2, ContactHold{});
  b.state.contact[0].normal = Vec3(-1, 0, 0);
  b.state.contact[1].normal = Vec3(1, 0, 0);
  std::vector<Real> offset(2);
  set_contact_planes(b.model, b.state, offset);
  CHECK(apply_strain_limit_on_contacts(b.model, b.state, 0.01, offset) == strain_limit_max_iterations);
  CHECK(max_spring_strain(b.model, b.state.x) == doctest::Approx(0.2).epsilon(1e-12));
  CHECK_FALSE(strain_limit_met(b.model, b.state.x));
}

namespace {

// Plain Gauss-Seidel sweeps that project every limited spring every time, with apply_strain_limit's arithmetic,
// relaxation and stopping rule, serial: the yardstick for the sweeps that skip settled springs. `after` runs
// after each sweep, as the planes and holds do after the collide stage.
template <class After>
int every_spring_limit(const Model& m, State& out, Real h, After&& after) {
  const auto excess_of = [&](Index s) {
    const Real len = (out.x[m.spring_b[s]] - out.x[m.spring_a[s]]).norm(), rest = m.spring_rest[s];
    return (len - rest) / rest - m.spring_max_strain[s];
  };
  const auto met_now = [&] {
    Real worst = -1e300;
    for (Index s : m.spring_colour_spring) worst = std::max(worst, excess_of(s));
    return worst <= 0.5 * strain_limit_tolerance;
  };
  if (met_now()) return 0;
  int it = 0;
  for (bool done = false; !done && it < strain_limit_max_iterations;) {
    const Real omega = it == 0 ? 1 : strain_limit_relaxation;
    Real met = -1e300;
    for (Index k = 0; k < Index(m.spring_colour_spring.size()); ++k) {  // colours in order, springs in order
      const Index s = m.spring_colour_spring[k], a = m.spring_a[s], b = m.spring_b[s];
      const Vec3 d = out.x[b] - out.x[a];
      const Real len = d.norm(), excess = (len - m.spring_rest[s]) / m.spring_rest[s] - m.spring_max_strain[s];
      met = std::max(met, excess);
      if (excess <= 0) continue;
      const Real wa = m.particle_inv_mass[a], wb = m.particle_inv_mass[b];
      const Real target = (1 + m.spring_max_strain[s]) * m.spring_rest[s];
      const Vec3 dx = (omega * (len - target) / ((wa + wb) * len)) * d;
      displace(out, a, wa * dx, h);
      displace(out, b, -wb * dx, h);
    }
    after(out);
    ++it;
    done = (it == 1 || met <= 0.5 * strain_limit_tolerance) && met_now();
  }
  return it;
}

bool same_bytes(const State& p, const State& q) {
  return std::memcmp(p.x.data(), q.x.data(), p.x.size() * sizeof(Vec3)) == 0 &&
         std::memcmp(p.v.data(), q.v.data(), p.v.size() * sizeof(Vec3)) == 0;
}

}  // namespace

TEST_CASE("sweeps that skip settled springs give the bytes and sweep counts of sweeps over every spring") {
  // The 32 x 32 dropped sheet through its first six steps (the drop the limit turns into a drape), held to 1 %
  // strain and without its tethers so that the sweeps do all the work; each step's integrated state goes to both.
  BuiltScene s = dropped_sheet(32);
  Model& m = s.model;
  m.tether_particle.clear();
  m.tether_pin.clear();
  m.tether_length.clear();
  m.spring_max_strain = ParamField(0.01);
  Workspace ws = make_workspace(m, s.options);
  const Real h = s.options.dt;
  State integrated = s.state;
  int sweeps = 0, reference = 0, steps_alike = 0;
  for (int k = 0; k < 6; ++k) {
    integrate_implicit(m, s.options.solver, s.state, integrated, ws, h);
    State every = integrated;
    sweeps += apply_strain_limit(m, integrated, h);
    reference += every_spring_limit(m, every, h, [](State&) {});
    steps_alike += same_bytes(integrated, every);
    std::swap(s.state, integrated);
  }
  MESSAGE("plain limit, 6 steps: " << sweeps << " sweeps, the yardstick " << reference);
  CHECK(sweeps > 20);
  CHECK(sweeps == reference);
  CHECK(steps_alike == 6);

  // After the collide stage: the left third of the sheet on planes (normal +y at its current height) and a hold,
  // as the cloth holds do, that moves a particle for another's move: each particle of the right third is kept no
  // more than 1 cm below the one a row before it. Both run after every sweep; the skipping sweeps must see their
  // moves, also of particles whose own springs had settled.
  State contacted = s.state;
  contacted.contact.assign(std::size_t(m.particle_count), ContactHold{});
  for (Index i = 0; i < m.particle_count; ++i)
    if (i % 32 < 10) contacted.contact[i].normal = Vec3(0, 1, 0);
  std::vector<Real> offset(std::size_t(m.particle_count));
  set_contact_planes(m, contacted, offset);
  const auto hold = [&](State& st, const MovedParticle& moved) {
    for (Index i = 32; i < m.particle_count; ++i) {
      const Real below = st.x[i - 32].y() - 0.01 - st.x[i].y();
      if (i % 32 > 21 && below > 0) {
        displace(st, i, Vec3(0, below, 0), h);
        moved(i);
      }
    }
  };
  const auto planes_and_hold = [&](State& st) {
    for (Index i = 0; i < m.particle_count; ++i) {
      const Vec3& n = st.contact[i].normal;
      const Real behind = offset[i] - n.dot(st.x[i]);
      if (behind > 0) displace(st, i, behind * n, h);
    }
    hold(st, [](Index) {});
  };
  State on_planes = contacted, every_on_planes = contacted;
  planes_and_hold(every_on_planes);  // apply_strain_limit_on_contacts starts with the planes and the hold
  const int contact_sweeps = apply_strain_limit_on_contacts(m, on_planes, h, offset, hold);
  const int contact_reference = every_spring_limit(m, every_on_planes, h, planes_and_hold);
  MESSAGE("on planes: " << contact_sweeps << " sweeps, the yardstick " << contact_reference);
  CHECK(contact_sweeps > 10);  // a real workload, not a limit met at once
  CHECK(contact_sweeps == contact_reference);
  CHECK(same_bytes(on_planes, every_on_planes));
}
