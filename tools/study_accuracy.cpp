// clothsim study accuracy: error against CPU time and against time step for every integrator, on reference
// problems with known answers (docs/accuracy.md reads the charts).
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "core/build_model.h"
#include "core/spring_system.h"
#include "io/atomic_file.h"
#include "systems/diagnostics.h"
#include "systems/forces.h"
#include "tools/cli_args.h"
#include "tools/commands.h"
#include "tools/studies.h"
#include "tools/study_chart.h"
#include "tools/study_run.h"

namespace clothsim::cli {
namespace {

const char* accuracy_help =
    "usage: clothsim study accuracy [--out DIR] [--quick]\n"
    "Runs every integrator over a ladder of 8 time steps, each half the last, on four problems: a spring-mass\n"
    "oscillator undamped and damped (against the closed form), a 32x32 sheet hanging from two corners for 1 s\n"
    "(against RK4 at a step 64x below the finest tested, checked by halving it once more) and the same sheet\n"
    "settling under heavy damping (against its static equilibrium). Writes into DIR (default study-accuracy):\n"
    "  accuracy.csv            problem, method, step, steps, force evaluations, CPU s, error, status\n"
    "  accuracy_orders.csv     the measured convergence order of each method on each problem\n"
    "  accuracy_reference.csv  how each reference was obtained and how much it moves when refined\n"
    "  work_precision.png/.svg error against CPU time, log-log (lower left is better)\n"
    "  error_vs_step.png/.svg  error against time step, measured order in the legend\n"
    "The error is the RMS distance of the free vertices to the reference at the end time, divided by the\n"
    "problem's size; the CPU time is the run's thread CPU time, the fastest of up to 3 repeats (runs over 0.5 s\n"
    "are timed once). Each run uses one thread; the ladders run side by side, one per core.\n"
    "A run that ends non-finite or farther from the reference than the problem's size counts as diverged;\n"
    "an error below 10x the reference's own change under refinement is marked unresolved. Neither is fitted\n"
    "or charted.\n"
    "  --quick   sheet runs of 1/32 s and 1/16 s, one timing per point, for the tests: not the study's figures";

constexpr int ladder_rungs = 8;         // time steps per ladder, each half the last
constexpr int reference_factor = 64;    // reference step = finest tested / 64

struct Problem {
  std::string name;                      // CSV key
  std::string title;                     // chart panel title
  Model model;
  State initial;
  Real end_time = 1;                     // s
  Real size = 1;                         // m: errors are RMS distances divided by this
  std::vector<Vec3> reference;           // positions at end_time
  std::string reference_how;             // for accuracy_reference.csv
  Real reference_step = 0;               // s, 0 for a closed form
  double reference_change = 0;           // RMS change of the reference when refined, / size
  // Errors below this cannot be told apart from the reference's own uncertainty: they are kept in the CSV as
  // "unresolved" and left out of the fitted orders and the charts. 10x the refinement change for a computed
  // reference, 0 for a closed form or an equilibrium (whose reference_change is a residual, not a distance).
  double resolution = 0;
  std::function<std::int64_t(const StudyMethod&)> coarsest_steps;  // steps over end_time at the top rung
};

struct Point {
  std::string problem, method;
  Real step;
  TimedRun run;
  double error;  // NaN when the run diverged
  const char* status;  // ok, diverged, unresolved (error below the problem's resolution)
};

// A mass on a spring, m u'' = -k u - c u', released from rest at u0: u = e^(-z w t) (u0 cos wd t + z w u0 / wd
// sin wd t), wd = w sqrt(1 - z^2). The motion stays on the spring's axis, where the spring force is linear.
Problem make_oscillator(Real zeta) {
  const Real rest = 0.1, mass = 0.01, omega = 2 * std::numbers::pi, u0 = 0.1 * rest;
  SpringSystemDesc d;
  d.positions = {Vec3(0, 0, 0), Vec3(rest, 0, 0)};
  d.masses = {0, mass};
  d.spring_a = {0};
  d.spring_b = {1};
  d.stiffness = mass * omega * omega;
  d.damping = 2 * zeta * mass * omega;
  BuiltScene b = build_spring_system(d);
  Problem p;
  p.name = zeta > 0 ? "oscillator_damped" : "oscillator";
  p.title = zeta > 0 ? "oscillator, damping ratio 0.1" : "oscillator, undamped";
  p.model = std::move(b.model);
  p.initial = std::move(b.state);
  p.initial.x[1].x() += u0;
  // w T = 2.25 pi: the sine and cosine of the phase are both 0.71 in size, so neither the amplitude error
  // (explicit Euler's) nor the phase error can vanish at the end time by coincidence.
  p.end_time = 1.125;
  p.size = rest;
  const Real wd = omega * std::sqrt(1 - zeta * zeta), t = p.end_time;
  const Real u = std::exp(-zeta * omega * t) * (u0 * std::cos(wd * t) + zeta * omega * u0 / wd * std::sin(wd * t));
  p.reference = {Vec3(0, 0, 0), Vec3(rest + u, 0, 0)};
  p.reference_how = "closed form";
  // First-order ladders start at h = 1/256 s, higher orders at 1/16 s: both stay in the asymptotic range and
  // above round-off over all 8 rungs.
  p.coarsest_steps = [](const StudyMethod& m) { return m.order == 1 ? std::int64_t(288) : std::int64_t(18); };
  return p;
}

// The hanging sheet of examples/hanging_sheet with softer springs (50 N/m: 8% peak strain under its own
// weight), so that the explicit methods are stable on part of the ladder.
SceneDesc sheet_scene(Real air_damping) {
  SceneDesc s;
  s.path = "(study sheet)";
  s.simulation.gravity = Vec3(0, -9.81, 0);
  s.forces.air_damping = air_damping;
  ClothDesc c;
  c.name = "sheet";
  c.grid_nx = c.grid_ny = 32;
  c.grid_w = c.grid_h = 1;
  c.density = 0.2;
  c.stiffness = 50;
  c.bend_scale = 0.2;
  c.damping = 0.02;
  c.pins = {0, 31};
  s.cloths.push_back(c);
  return s;
}

Problem make_sheet_base(Real air_damping, Real end_time) {
  const SceneDesc scene = sheet_scene(air_damping);
  BuiltScene b = build_model(scene, {make_cloth_grid(scene.cloths[0])});
  Problem p;
  p.model = std::move(b.model);
  p.initial = std::move(b.state);
  p.end_time = end_time;
  p.size = 1;
  // One ladder for every method, 64 to 8192 steps per second: the explicit methods diverge on its top rungs.
  p.coarsest_steps = [end_time](const StudyMethod&) { return std::llround(64 * end_time); };
  return p;
}

// The hanging sheet against RK4 at a step 64x below the finest tested, and again at half that step to show
// the reference is converged; the two runs go in parallel, one per core.
Problem make_sheet(bool quick) {
  Problem p = make_sheet_base(0.1, quick ? 1.0 / 32 : 1.0);
  p.name = "sheet";
  p.title = quick ? "32x32 sheet, 1/32 s" : "32x32 sheet hanging for 1 s";
  const StudyMethod& any = study_methods.front();
  const std::int64_t steps = p.coarsest_steps(any) * (std::int64_t(1) << (ladder_rungs - 1)) * reference_factor;
  p.reference_step = p.end_time / Real(steps);
  TimedRun ref, finer;
  std::thread second([&] { finer = timed_run(p.model, p.initial, Integrator::rk4, p.reference_step / 2, 2 * steps, 1); });
  ref = timed_run(p.model, p.initial, Integrator::rk4, p.reference_step, steps, 1);
  second.join();
  p.reference = ref.state.x;
  p.reference_change = rms_distance(p.model, ref.state.x, finer.state.x) / p.size;
  p.reference_how = "rk4 at step/64 of the finest tested";
  p.resolution = 10 * p.reference_change;
  return p;
}

// The sheet under heavy air damping (8 /s, past critical for its swinging mode) against its static
// equilibrium: found by running symplectic Euler at a step well inside its limit until the sheet is still,
// the result does not depend on the integrator that finds it. reference_change is the largest acceleration
// left at the equilibrium with zero velocity, m/s^2: the force balance, checked independently of the run.
Problem make_sheet_equilibrium(bool quick) {
  Problem p = make_sheet_base(8.0, quick ? 1.0 / 16 : 6.0);
  p.name = "sheet_equilibrium";
  p.title = quick ? "sheet settling, 1/16 s" : "sheet settling to equilibrium, 6 s";
  p.reference_step = 1.0 / 4096;
  const std::int64_t chunk = 4096;
  State state = p.initial;
  TimedRun run;
  for (int second = 0; second < 60; ++second) {
    run = timed_run(p.model, state, Integrator::symplectic, p.reference_step, chunk, 1);
    state = run.state;
    if (kinetic_energy(p.model, state.v) < (quick ? 1e-12 : 1e-24)) break;
  }
  std::fprintf(stderr, "  equilibrium reached after %lld steps\n", static_cast<long long>(state.step));
  state.v.assign(state.v.size(), Vec3::Zero());
  Model still = p.model;
  Workspace ws = make_workspace(still, SimOptions{});
  eval_forces(still, state.x, state.v, 0, ws);
  double residual = 0;
  for (Index i = 0; i < still.particle_count; ++i) residual = std::max(residual, double(ws.f[i].norm()));
  p.reference = state.x;
  p.reference_change = residual;
  p.reference_how = "static equilibrium (reference_change: largest residual acceleration m/s^2)";
  return p;
}

// A run whose RMS distance to the reference exceeds the problem's size has blown up, finite or not.
constexpr double diverged_error = 1;

// One method's ladder on one problem: `ladder_rungs` steps, each half the last.
std::vector<Point> run_ladder(const Problem& p, const StudyMethod& m, int repeats) {
  std::vector<Point> points;
  std::int64_t steps = p.coarsest_steps(m);
  for (int rung = 0; rung < ladder_rungs; ++rung, steps *= 2) {
    const Real h = p.end_time / Real(steps);
    Point pt{p.name, m.name(), h, timed_run(p.model, p.initial, m.integrator, h, steps, repeats), NAN, "ok"};
    if (pt.run.finite) pt.error = rms_distance(p.model, pt.run.state.x, p.reference) / p.size;
    if (!(pt.error <= diverged_error)) pt.error = NAN;
    if (!std::isfinite(pt.error)) pt.status = "diverged";
    else if (pt.error < p.resolution) pt.status = "unresolved";
    std::fprintf(stderr, "  %-18s %-10s h=%-10.4g error %-10.3g cpu %.3g s\n", p.name.c_str(), m.name(), h, pt.error,
                 pt.run.cpu_seconds);
    points.push_back(std::move(pt));
  }
  return points;
}

double measured_order(const std::vector<Point>& points, const std::string& problem, const std::string& method) {
  std::vector<double> h, e;
  for (const Point& p : points)
    if (p.problem == problem && p.method == method && p.status == std::string_view("ok")) {
      h.push_back(p.step);
      e.push_back(p.error);
    }
  return fit_order(h, e);
}

// One panel per problem, one curve per method, read from accuracy.csv by gnuplot's column filters.
std::string chart_commands(const std::vector<Problem>& problems, const std::vector<Point>& points, bool work) {
  std::string s = "set multiplot layout 2,2 title " +
                  quote_text(work ? "Work-precision: error against CPU time (lower left is better)"
                              : "Error against time step (measured convergence order in the legend)") +
                  "\nset logscale xy\nset format xy '10^{%L}'\nset grid\nset key bottom right font ',9'\n" +
                  "set ylabel 'error (RMS distance / size)'\n" +
                  (work ? "set xlabel 'CPU time, s'\n" : "set xlabel 'time step, s'\n");
  for (const Problem& p : problems) {
    s += "set title " + quote_text(p.title) + "\nplot ";
    for (std::size_t k = 0; k < study_methods.size(); ++k) {
      const std::string method = study_methods[k].name();
      std::string title = method;
      if (!work) title += " (order " + csv_number(std::round(100 * measured_order(points, p.name, method)) / 100) + ")";
      s += std::string(k ? ", \\\n     " : "") + "'accuracy.csv' every ::1 using " +
           "(strcol(1) eq '" + p.name + "' && strcol(2) eq '" + method + "' && strcol(8) eq 'ok' ? $" +
           (work ? "6" : "3") + " : NaN):7 with linespoints lw 2 pt " + std::to_string(k + 5) + " title " +
           quote_text(title);
    }
    s += "\n";
  }
  return s + "unset multiplot\n";
}

}  // namespace

int study_accuracy(int argc, char** argv) {
  const StudyOptions options = parse_study_options(argc, argv, "study-accuracy");
  if (options.help) { std::puts(accuracy_help); return exit_ok; }
  const bool quick = options.quick;
  const std::string& out = options.out;
  // One thread per run: CPU time then measures the integrator's work alone, and the repeats compare alike.
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);

  std::vector<Problem> problems;
  problems.push_back(make_oscillator(0));
  problems.push_back(make_oscillator(0.1));
  std::fprintf(stderr, "clothsim study accuracy: references for the sheets\n");
  {
    // The equilibrium's reference beside the sheet's (which runs its own confirmation on a second thread).
    Problem equilibrium;
    std::thread beside([&] { equilibrium = make_sheet_equilibrium(quick); });
    problems.push_back(make_sheet(quick));
    beside.join();
    problems.push_back(std::move(equilibrium));
  }

  // Every (problem, method) ladder is independent: they run side by side, each timed by its own thread's CPU
  // clock, and are gathered back in the fixed order of problems and methods.
  const std::size_t method_count = study_methods.size();
  std::vector<std::vector<Point>> ladders(problems.size() * method_count);
  run_tasks_in_parallel(ladders.size(), [&](std::size_t k) {
    ladders[k] = run_ladder(problems[k / method_count], study_methods[k % method_count], quick ? 1 : 3);
  });
  std::vector<Point> points;
  for (std::vector<Point>& ladder : ladders)
    points.insert(points.end(), std::make_move_iterator(ladder.begin()), std::make_move_iterator(ladder.end()));

  std::string csv = "problem,method,step_s,steps,force_evaluations,cpu_s,error,status\n";
  for (const Point& p : points)
    csv += p.problem + "," + p.method + "," + csv_number(p.step) + "," + std::to_string(p.run.steps) + "," +
           std::to_string(p.run.force_evaluations) + "," + csv_number(p.run.cpu_seconds) + "," +
           csv_number(p.error) + "," + p.status + "\n";
  std::string orders = "problem,method,measured_order\n";
  for (const Problem& p : problems)
    for (const StudyMethod& m : study_methods)
      orders += p.name + "," + m.name() + "," + csv_number(measured_order(points, p.name, m.name())) + "\n";
  std::string refs = "problem,reference,reference_step_s,reference_change,smallest_error\n";
  for (const Problem& p : problems) {
    double smallest = INFINITY;
    for (const Point& pt : points)
      if (pt.problem == p.name && std::isfinite(pt.error)) smallest = std::min(smallest, pt.error);
    refs += p.name + "," + p.reference_how + "," + csv_number(p.reference_step) + "," +
            csv_number(p.reference_change) + "," + csv_number(smallest) + "\n";
  }
  const std::filesystem::path dir(out);
  io::write_file_atomic((dir / "accuracy.csv").string(), csv);
  io::write_file_atomic((dir / "accuracy_orders.csv").string(), orders);
  io::write_file_atomic((dir / "accuracy_reference.csv").string(), refs);
  render_chart(out, "work_precision", 1100, 850, chart_commands(problems, points, true));
  render_chart(out, "error_vs_step", 1100, 850, chart_commands(problems, points, false));
  std::fputs(orders.c_str(), stdout);
  return exit_ok;
}

}  // namespace clothsim::cli
