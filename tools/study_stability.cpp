// clothsim study stability: the largest time step each integrator survives on undamped springs, and the largest
// stiffness at a fixed step, found by bisection and charted against the linear stability theory.
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "core/csr.h"
#include "core/spring_system.h"
#include "io/atomic_file.h"
#include "systems/diagnostics.h"
#include "systems/energy.h"
#include "systems/step.h"
#include "tools/cli_args.h"
#include "tools/commands.h"
#include "tools/studies.h"
#include "tools/study_chart.h"
#include "tools/study_run.h"

namespace clothsim::cli {
namespace {

const char* stability_help =
    "usage: clothsim study stability [--out DIR] [--quick]\n"
    "A chain of 8 masses between two pinned ends, undamped, started in its stiffest mode. For spring stiffness\n"
    "across four decades, bisection on the time step finds the largest step at which each integrator keeps the\n"
    "energy within a factor 2 of its start over 100 periods of the stiffest mode; then, at a fixed step of 1 ms,\n"
    "the largest stiffness. Theory, with w_max the chain's highest frequency (exact): symplectic Euler\n"
    "h < 2/w_max, RK4 h < 2 sqrt(2)/w_max, explicit Euler unstable at any step (its energy grows by 1 + (h w)^2\n"
    "a step, so the 2x bound over 100 periods fails above h w = ln 2 / (200 pi)). Writes into DIR (default\n"
    "study-stability): stability_step.csv, stability_stiffness.csv, stability.png and stability.svg.\n"
    "  --quick   3 stiffnesses instead of 9 and a 1% bisection tolerance instead of 0.1%, for the tests";

constexpr int chain_masses = 8;
constexpr Real chain_mass = 0.01;   // kg per particle
constexpr Real chain_rest = 0.1;    // m per spring
constexpr Real fixed_step = 1e-3;   // s, for the largest-stiffness sweep
constexpr Real pi = std::numbers::pi;

// w_max h at the stability limit for undamped springs; INFINITY where every step is stable. Explicit Euler has
// no stable step: its entry is where the 2x energy bound over 100 periods gives way, as the study measures it.
double theory_limit(Integrator integrator) {
  switch (integrator) {
    case Integrator::euler: return std::log(2.0) / (200 * pi);
    case Integrator::symplectic: return 2;
    case Integrator::rk4: return 2 * std::numbers::sqrt2;
    case Integrator::implicit: return INFINITY;  // backward Euler is A-stable: stable at every step
  }
  return NAN;
}

// The fixed-fixed discrete string: n masses m joined by n + 1 springs k, whose highest mode is
// w_max = 2 sqrt(k/m) sin(n pi / (2 (n + 1))) with shape sin(i n pi / (n + 1)), i = 1..n.
struct Chain {
  Model model;
  State start;
  Real omega_max = 0;
};

Chain make_chain(Real stiffness) {
  SpringSystemDesc d;
  for (int i = 0; i <= chain_masses + 1; ++i) {
    d.positions.push_back(Vec3(chain_rest * i, 0, 0));
    d.masses.push_back(i == 0 || i == chain_masses + 1 ? 0.0 : chain_mass);
    if (i > 0) { d.spring_a.push_back(i - 1); d.spring_b.push_back(i); }
  }
  d.stiffness = stiffness;
  BuiltScene b = build_spring_system(d);
  Chain c;
  c.model = std::move(b.model);
  c.start = std::move(b.state);
  const int n = chain_masses;
  c.omega_max = 2 * std::sqrt(stiffness / chain_mass) * std::sin(n * pi / (2.0 * (n + 1)));
  // The stiffest mode at a 45 degree phase (w u = v): for symplectic Euler the energy along a stable orbit
  // peaks there, so the 2x bound tests growth; a start from rest would see the bounded orbit's own swing of
  // 1/(1 - h w / 2) and fail at half the true limit. RK4 and explicit Euler scale the energy alike at every phase.
  const Real amplitude = 1e-3 * chain_rest;
  for (int i = 1; i <= n; ++i) {
    const Real shape = amplitude * std::sin(i * n * pi / (n + 1));
    c.start.x[i].x() += shape;
    c.start.v[i].x() = c.omega_max * shape;
  }
  return c;
}

Real energy(const Model& m, const State& s) { return kinetic_energy(m, s.v) + spring_potential_energy(m, s.x); }

// Energy within a factor 2 of its start over 100 periods of the stiffest mode (and at least 100 steps).
bool stays_bounded(const Chain& c, Integrator integrator, Real h) {
  Model model = c.model;
  ensure_particle_springs(model, integrator);
  SimOptions options;
  options.integrator = integrator;
  Workspace ws = make_workspace(model, options);
  State state = c.start, scratch = c.start;
  const Real e0 = energy(model, state);
  const std::int64_t steps = std::max<std::int64_t>(100, std::llround(std::ceil(100 * 2 * pi / (c.omega_max * h))));
  for (std::int64_t k = 0; k < steps; ++k) {
    step(model, options, state, scratch, ws, h);
    std::swap(state, scratch);
    if (!(energy(model, state) <= 2 * e0)) return false;
  }
  return true;
}

struct Limit {
  double value = 0;       // largest bounded value found
  bool at_cap = false;    // still bounded at the search cap: no limit below it
};

// Largest x with bounded(x), assuming bounded holds below a threshold and fails above it: doubling or
// halving from `guess` to bracket it, then geometric bisection to a relative width `tolerance`.
Limit largest_bounded(const std::function<bool(double)>& bounded, double guess, double cap, double tolerance) {
  double lo = guess, hi = guess;
  if (bounded(guess)) {
    while (true) {
      hi = 2 * lo;
      if (hi > cap) return {cap, true};
      if (!bounded(hi)) break;
      lo = hi;
    }
  } else {
    do {
      hi = lo;
      lo = hi / 2;
      if (lo < guess * 1e-9) return {0, false};
    } while (!bounded(lo));
  }
  while (hi / lo > 1 + tolerance) {
    const double mid = std::sqrt(lo * hi);
    (bounded(mid) ? lo : hi) = mid;
  }
  return {lo, false};
}

std::string chart_commands() {
  std::string s =
      "set multiplot layout 1,2 title 'Stability of the integrators on undamped springs (chain of 8 masses)'\n"
      "set grid\nset logscale xy\nset format xy '10^{%L}'\nset key bottom left font ',9'\n"
      "set title 'Largest bounded time step against stiffness'\n"
      "set xlabel 'spring stiffness, N/m'\nset ylabel 'time step, s'\nplot ";
  for (std::size_t k = 0; k < study_methods.size(); ++k) {
    const std::string m = study_methods[k].name(), filter = "strcol(1) eq '" + m + "'", colour = std::to_string(k + 1);
    s += std::string(k ? ", \\\n     " : "");
    if (std::isfinite(theory_limit(study_methods[k].integrator))) {
      s += "'stability_step.csv' every ::1 using (" + filter + " ? $2 : NaN):(strcol(6) eq 'limit' ? $4 : NaN) " +
           "with points pt " + std::to_string(k + 5) + " ps 1.5 lc " + colour + " title '" + m + " measured', " +
           "'stability_step.csv' every ::1 using (" + filter + " ? $2 : NaN):5 with lines dt 2 lc " + colour +
           " title '" + m + " theory'";
    } else {
      // No limit in theory (backward Euler): the runs still bounded at the search cap (1000 / w_max) are drawn
      // at the cap, since the limit, if any, lies above it.
      s += "'stability_step.csv' every ::1 using (" + filter + " ? $2 : NaN):(strcol(6) eq 'bounded_at_cap' ? $4 : " +
           "NaN) with points pt 8 ps 1.5 lc " + colour + " title '" + m + " bounded at the search cap'";
    }
  }
  s += "\nset title 'Largest bounded stiffness at a 1 ms step'\nunset logscale x\nset format x '%g'\n"
       "set xlabel ''\nset ylabel 'spring stiffness, N/m'\nset xrange [-0.5:" +
       std::to_string(study_methods.size() - 0.5) + "]\nset key top left\n"
       "plot 'stability_stiffness.csv' every ::1 using 0:(strcol(6) eq 'limit' ? $3 : NaN):xtic(1) with points "
       "pt 7 ps 2 title 'measured', 'stability_stiffness.csv' every ::1 using 0:4 with points pt 6 ps 3 "
       "title 'theory', 'stability_stiffness.csv' every ::1 using 0:(strcol(6) eq 'bounded_at_cap' ? $3 : NaN) "
       "with points pt 8 ps 2 lc 7 title 'bounded at the search cap'\nunset multiplot\n";
  return s;
}

}  // namespace

int study_stability(int argc, char** argv) {
  const StudyOptions options = parse_study_options(argc, argv, "study-stability");
  if (options.help) { std::puts(stability_help); return exit_ok; }
  const bool quick = options.quick;
  const std::string& out = options.out;
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const double tolerance = quick ? 1e-2 : 1e-3;
  // The search stops at 1000 / w_max: over 350x the RK4 limit, where only an unconditionally stable method goes.
  const double cap_hw = 1000;

  std::vector<double> stiffnesses;
  for (int j = 0; j <= 8; j += quick ? 4 : 1) stiffnesses.push_back(std::pow(10.0, 1 + 0.5 * j));

  // Every (method, stiffness) search is independent: they run side by side, one per core, and their rows are
  // gathered back in a fixed order. Each run uses one thread, so the results do not depend on the core count.
  std::vector<std::string> step_rows(study_methods.size() * stiffnesses.size());
  run_tasks_in_parallel(step_rows.size(), [&](std::size_t task) {
    const StudyMethod& m = study_methods[task / stiffnesses.size()];
    const double k = stiffnesses[task % stiffnesses.size()];
    const Chain chain = make_chain(k);
    const double w = chain.omega_max, theory = theory_limit(m.integrator) / w;
    const Limit lim = largest_bounded([&](double h) { return stays_bounded(chain, m.integrator, h); }, 3 / w,
                                      cap_hw / w, tolerance);
    std::fprintf(stderr, "  %-10s k=%-8.3g w_max=%-8.4g largest bounded step %.5g s%s, theory %.5g s\n", m.name(), k,
                 w, lim.value, lim.at_cap ? " (search cap)" : "", theory);
    step_rows[task] = std::string(m.name()) + "," + csv_number(k) + "," + csv_number(w) + "," +
                      csv_number(lim.value) + "," + csv_number(theory) + "," +
                      (lim.at_cap ? "bounded_at_cap" : "limit") + "," +
                      csv_number(std::isfinite(theory) ? lim.value / theory : NAN) + "\n";
  });
  std::string steps_csv = "method,stiffness_n_per_m,omega_max,measured_step_s,theory_step_s,status,ratio\n";
  for (const std::string& row : step_rows) steps_csv += row;

  // Largest stiffness at a fixed step: w_max(k) = c sqrt(k), so the theory is k = (limit / (h c))^2.
  const double c_unit = make_chain(1).omega_max;
  std::vector<std::string> stiff_rows(study_methods.size());
  run_tasks_in_parallel(stiff_rows.size(), [&](std::size_t task) {
    const StudyMethod& m = study_methods[task];
    const double theory = std::pow(theory_limit(m.integrator) / (fixed_step * c_unit), 2);
    const double guess = std::pow(3 / (fixed_step * c_unit), 2);
    const Limit lim = largest_bounded(
        [&](double k) { return stays_bounded(make_chain(k), m.integrator, fixed_step); }, guess,
        guess * cap_hw * cap_hw, tolerance);
    std::fprintf(stderr, "  %-10s h=%g s: largest bounded stiffness %.5g N/m%s, theory %.5g N/m\n", m.name(),
                 fixed_step, lim.value, lim.at_cap ? " (search cap)" : "", theory);
    stiff_rows[task] = std::string(m.name()) + "," + csv_number(fixed_step) + "," + csv_number(lim.value) + "," +
                       csv_number(theory) + "," + csv_number(std::isfinite(theory) ? lim.value / theory : NAN) + "," +
                       (lim.at_cap ? "bounded_at_cap" : "limit") + "\n";
  });
  std::string stiff_csv = "method,step_s,measured_stiffness_n_per_m,theory_stiffness_n_per_m,ratio,status\n";
  for (const std::string& row : stiff_rows) stiff_csv += row;

  const std::filesystem::path dir(out);
  io::write_file_atomic((dir / "stability_step.csv").string(), steps_csv);
  io::write_file_atomic((dir / "stability_stiffness.csv").string(), stiff_csv);
  render_chart(out, "stability", 1200, 550, chart_commands());
  std::fputs(steps_csv.c_str(), stdout);
  return exit_ok;
}

}  // namespace clothsim::cli
