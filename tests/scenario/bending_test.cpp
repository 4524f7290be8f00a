// Dihedral bending through the whole step: a cantilevered strip under small gravity against Euler-Bernoulli's
// tip deflection q L^4 / (8 D) as the grid is refined, the same static deflection from every integrator (and from
// backward Euler far past the explicit bound, with the hinges' Jacobian), the Cholesky factor's hinge blocks, the
// step bounds auto and validate apply, and the same bytes at 1 and 2 threads.
#include <doctest/doctest.h>

#include <cmath>

#include "sim/step_advice.h"
#include "systems/auto_step.h"
#include "systems/bend_forces.h"
#include "systems/stability.h"
#include "systems/step.h"
#include "tests/support/scene_fixtures.h"
#include "tests/support/thread_bytes.h"

using namespace clothsim;

namespace {

// A strip of length L (x) and width W (z) on the grid of spacing a = L / (n - 1), bending modulus D, density rho,
// under gravity g along -y, clamped by pinning its first two columns: the first hinge line is the second column,
// and its finite-difference clamp (w = w' = 0) sits half a spacing before it, so the free length is L - a/2. Soft
// undamped stretch springs (10 N/m: the tension gravity puts in them strains them by ~1e-7) and air damping at
// the first mode's critical value 2 omega_1 let it settle.
struct Strip {
  Real L = 0.1, W = 0.025, D = 1e-4, rho = 0.2, g = 4e-3;
  int n = 9;
  int rows() const { return int(std::lround(W / spacing())) + 1; }
  Real spacing() const { return L / (n - 1); }
  Real free_length() const { return L - 0.5 * spacing(); }
  // Euler-Bernoulli: a clamped beam under a uniform load q per unit length, w = q l^4 / (8 EI); per unit width
  // q = rho g and EI = D. Here 1.0e-4 m at l = L: 0.1% of the length, well inside linear theory.
  Real beam_tip() const { return rho * g * std::pow(free_length(), 4) / (8 * D); }
  Real omega_1() const { return 3.516 * std::sqrt(D / (rho * std::pow(free_length(), 4))); }
};

BuiltScene strip_scene(const Strip& s, Integrator integrator) {
  SceneDesc scene = test::grid_scene(s.n, s.rows(), 1, integrator);
  scene.simulation.gravity = Vec3(0, -s.g, 0);
  scene.forces.air_damping = 2 * s.omega_1();
  ClothDesc& c = scene.cloths[0];
  c.grid_w = s.L;
  c.grid_h = (s.rows() - 1) * s.spacing();
  c.density = s.rho;
  c.stiffness = 10;
  c.damping = 0;
  c.bending = Bending::dihedral;
  c.bend_modulus = s.D;
  for (int j = 0; j < c.grid_ny; ++j)
    for (int i = 0; i < 2; ++i) c.pins.push_back(j * s.n + i);
  return test::build(scene);
}

// Mean deflection of the free end's column after `seconds`, stepped at `step_size` or, when it is 0, at the largest
// step the explicit integrators' bound allows with a margin: symplectic, RK4 and implicit by 2/omega, explicit
// Euler by gamma/omega^2 (docs/stability.md); omega from the springs' estimate and twice the largest hinge's.
Real tip_deflection(const Strip& s, Integrator integrator, Real seconds, Real step_size = 0) {
  BuiltScene b = strip_scene(s, integrator);
  const Model& m = b.model;
  const Real omega = std::hypot(estimate_omega_max(m, b.state.x), 2 * estimate_hinge_omega(m, b.state.x));
  const Real bound = integrator == Integrator::euler ? 0.5 * m.air_damping / (omega * omega) : 0.5 / omega;
  const Real h = step_size > 0 ? step_size : bound;
  const auto steps = std::int64_t(std::ceil(seconds / h));
  Workspace ws = make_workspace(m, b.options);
  State scratch = b.state;
  for (std::int64_t k = 0; k < steps; ++k) {
    step(m, b.options, b.state, scratch, ws, seconds / steps);
    std::swap(b.state, scratch);
  }
  Real sum = 0;
  for (int j = 0; j < s.rows(); ++j) sum -= b.state.x[j * s.n + s.n - 1].y();
  return sum / s.rows();
}

}  // namespace

// The grid's one diagonal direction makes the discrete energy anisotropic (docs/model.md): cylinders about x, z
// or the diagonal store D/2 k^2 exactly, but twist costs 3x and couples to bending, so a strip free to twist
// has e = (D/2) 0.8 k^2 at best (k_zz = k_xz = k/5 minimise it). The clamp holds the root untwisted, so the
// converged tip lies between the beam's answer and 1.25 times it. Resolution independence is the claim tested:
// successive refinements change the tip by a shrinking amount and the extrapolated tip is in that bracket.
// This and the next are slow (explicit runs to a static tip, 2-3 minutes each under the sanitizers): the hinges'
// kernels stay under the sanitizers through tests/unit/bend_forces_test.cpp and the implicit and thread cases below.
TEST_CASE("a cantilevered strip with dihedral bending converges to a tip within 1 to 1.25 x q L^4 / (8 D)" * doctest::test_suite("slow")) {
  std::vector<Real> ratio;
  for (int n : {9, 17, 33}) {
    Strip s;
    s.n = n;
    const Real w = tip_deflection(s, Integrator::symplectic, 2.0);
    ratio.push_back(w / s.beam_tip());
    MESSAGE("n = " << n << ": tip " << w << " m, beam " << s.beam_tip() << " m, ratio " << ratio.back());
  }
  const Real d1 = ratio[1] - ratio[0], d2 = ratio[2] - ratio[1];
  CHECK(std::abs(d2) < 0.6 * std::abs(d1));  // first order or better: the change at least nearly halves
  const Real limit = ratio[2] + d2 * d2 / (d1 - d2);  // geometric (Aitken) extrapolation
  MESSAGE("extrapolated tip / beam: " << limit);
  CHECK(limit > 1.0);
  CHECK(limit < 1.25);
}

TEST_CASE("every integrator brings the dihedral cantilever to the same static tip" * doctest::test_suite("slow")) {
  Strip s;
  const Real reference = tip_deflection(s, Integrator::implicit, 2.0);
  for (Integrator integrator : {Integrator::euler, Integrator::symplectic, Integrator::rk4}) {
    CAPTURE(integrator_name(integrator));
    CHECK(tip_deflection(s, integrator, 2.0) == doctest::Approx(reference).epsilon(1e-3));
  }
}

TEST_CASE("backward Euler with the hinges' Jacobian in its matrix brings the cantilever to the same tip at 20x the explicit bound") {
  // Without the Jacobian the implicit step is symplectic Euler for bending, unstable past 1 / omega_h
  // (docs/stability.md): at 20x that bound the strip's bending modes would grow each step.
  Strip s;
  const BuiltScene b = strip_scene(s, Integrator::implicit);
  const Real bound = hinge_step_limit(b.model, b.state.x);
  const Real reference = tip_deflection(s, Integrator::implicit, 2.0);
  const Real tip = tip_deflection(s, Integrator::implicit, 2.0, 20 * bound);
  MESSAGE("explicit bound " << bound << " s; tip " << tip << " m at 20x it, " << reference << " m at 0.5 / omega");
  CHECK(tip == doctest::Approx(reference).epsilon(1e-3));
}

TEST_CASE("the Cholesky factor holds the hinges: a fresh factor solves a bent step in one iteration, as the others do") {
  // The factor's hinge blocks h^2 u_k u_l^T (and their transposes) must be the CG product's exactly, or a fresh
  // factor leaves more than one iteration. Jacobi and multigrid reach the same velocities to the tolerance.
  Strip s;
  s.n = 17;
  std::vector<Vec3> reference;
  for (Preconditioner pc : {Preconditioner::cholesky, Preconditioner::jacobi, Preconditioner::multigrid}) {
    CAPTURE(int(pc));
    BuiltScene b = strip_scene(s, Integrator::implicit);
    b.options.solver.preconditioner = pc;
    b.options.solver.cg_tolerance = 1e-10;
    b.options.solver.cg_max_iterations = 10000;
    for (std::size_t i = 0; i < b.state.x.size(); ++i)  // a bent, moving start: the hinges are far from rest
      if (b.model.particle_inv_mass[i] > 0) {
        b.state.x[i].y() += 0.004 * std::pow(b.state.x[i].x() / s.L, 2) * (1 + b.state.x[i].z() / s.W);
        b.state.v[i] = Vec3(0, 0.05 * std::sin(40 * b.state.x[i].x()), 0.02);
      }
    Workspace ws = make_workspace(b.model, b.options);
    State out = b.state;
    const StepResult r = step(b.model, b.options, b.state, out, ws, 0.01);
    MESSAGE("preconditioner " << int(pc) << ": " << r.solve.cg_iterations << " CG iterations");
    CHECK(r.solve.cg_residual < 1e-10);
    if (pc == Preconditioner::cholesky) {
      CHECK(r.solve.cg_iterations == 1);
      reference = out.v;
    }
    Real worst = 0, scale = 0;
    for (std::size_t i = 0; i < out.v.size(); ++i) {
      worst = std::max(worst, (out.v[i] - reference[i]).norm());
      scale = std::max(scale, (out.v[i] - b.state.v[i]).norm());
    }
    CHECK(worst < 1e-6 * scale);
  }
}

TEST_CASE("dihedral bending gives the same bytes at 1 and 2 threads") {
  for (Integrator integrator : {Integrator::symplectic, Integrator::implicit}) {
    // 60 x 60: 3,600 particles and 10,325 hinges, several blocks of particle_grain each.
    SceneDesc scene = test::grid_scene(60, 60, 1, integrator, 2e-4);
    scene.cloths[0].bending = Bending::dihedral;
    scene.cloths[0].bend_modulus = 1e-3;
    scene.cloths[0].pins = {0, 59};
    const BuiltScene b = test::build(scene);
    REQUIRE(b.model.hinge_count == 10325);
    CAPTURE(integrator_name(integrator));
    test::check_same_bytes_at_1_and_2_threads(b, 20);
  }
}

TEST_CASE("timestep=auto keeps the explicit integrators below the hinges' bound, and backward Euler past it") {
  // The strip at 17 columns (a = 6.25 mm, D = 1e-4 N m): symplectic Euler's springs allow far more than the
  // hinges' 1 / omega_h, so the hinges choose its step; backward Euler, with their Jacobian in its matrix, takes
  // its own target (0.7 x 20 ms, or the frame) as with bend springs.
  Strip s;
  s.n = 17;
  BuiltScene b = strip_scene(s, Integrator::symplectic);
  const Real omega_h = estimate_hinge_omega(b.model, b.state.x);
  REQUIRE(omega_h > 0);
  CHECK(hinge_step_limit(b.model, b.state.x) == doctest::Approx(1 / omega_h).epsilon(1e-15));
  const StableSteps limits = model_stable_steps(b.model, b.state.x);
  CHECK(limits.hinges == hinge_step_limit(b.model, b.state.x));
  MESSAGE("symplectic " << limits.symplectic << " s for the springs, " << limits.hinges << " s for the hinges");
  CHECK(limits.symplectic > 1.5 * limits.hinges);  // the springs alone would allow 1.8 times more
  CHECK(stable_step_limit(limits, Integrator::symplectic) == limits.hinges);
  SimOptions o = b.options;
  o.auto_step = true;
  choose_auto_step(b.model, o, b.state.x, "strip");
  CHECK(o.dt <= o.step_safety / omega_h);
  CHECK(o.dt > 0.5 * o.step_safety / omega_h);  // the largest step that divides the frame: at least half
  MESSAGE("omega_h " << omega_h << " rad/s, symplectic auto step " << o.dt << " s");
  // validate warns of a fixed step past the hinges' bound, though the springs alone would allow it.
  SimOptions fixed = b.options;
  fixed.dt = 0.5 * (limits.hinges + limits.symplectic);
  const std::string warning = sim::step_warning(fixed, limits);
  MESSAGE(warning);
  CHECK(warning.find("exceeds the symplectic Euler limit") != std::string::npos);
  CHECK(warning.find("dihedral hinges") != std::string::npos);
  fixed.dt = 0.5 * o.step_safety * limits.hinges;
  CHECK(sim::step_warning(fixed, limits).empty());
  BuiltScene ib = strip_scene(s, Integrator::implicit);
  SimOptions io = ib.options;
  io.auto_step = true;
  choose_auto_step(ib.model, io, ib.state.x, "strip");
  CHECK(io.dt == doctest::Approx(std::min(1 / io.fps, io.step_safety * 0.02)));  // a frame, or backward Euler's target
  CHECK(io.dt > 5 * o.dt);
}
