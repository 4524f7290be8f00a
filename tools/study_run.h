#pragma once
// What the studies share: the list of integrators they compare, a timed run of a fixed number of steps, and
// the least-squares convergence order.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/model.h"

namespace clothsim::cli {

struct StudyMethod {
  Integrator integrator;
  int order;  // formal order of accuracy: where an oscillator's step ladder starts
  const char* name() const { return integrator_name(integrator); }  // as in the scene file and the CSV
};

// Every integrator the studies chart and the tests check; a new one joins them all with one line here.
inline const std::vector<StudyMethod> study_methods{
    {Integrator::euler, 1},
    {Integrator::symplectic, 1},
    {Integrator::rk4, 4},
    {Integrator::implicit, 1},
};

struct TimedRun {
  State state;                  // after the last step
  double cpu_seconds = 0;       // thread CPU time of the fastest repeat (sim/cpu_clock.h)
  std::int64_t force_evaluations = 0;
  std::int64_t steps = 0;
  bool finite = true;           // every position and velocity finite at the end
};

// `steps` steps of h from `initial` with `integrator` and the default solver settings, in a workspace sized for them.
// Runs that take under `repeat_below` CPU seconds are repeated up to `repeats` times and the fastest kept:
// longer runs vary less than the spread the repeats would remove. A run that turns non-finite stops early.
TimedRun timed_run(const Model& model, const State& initial, Integrator integrator, Real h, std::int64_t steps,
                   int repeats = 3, double repeat_below = 0.5);

// The options every study takes: --out DIR (created and checked writable) and --quick. help is set for --help,
// which the caller answers; a positional argument is a usage error.
struct StudyOptions {
  std::string out;
  bool quick = false;
  bool help = false;
};
StudyOptions parse_study_options(int argc, char** argv, const std::string& default_out);

// A number for the CSV files: 12 significant digits, "nan" and "inf" as gnuplot reads them.
std::string csv_number(double v);

// Calls task(0) .. task(count - 1), each once, on as many threads as the machine has cores (none hard-wired).
// The studies' runs are independent and each is timed by its own thread's CPU clock, so running them side by
// side changes no figure but the wall time (sim/cpu_clock.h).
void run_tasks_in_parallel(std::size_t count, const std::function<void(std::size_t)>& task);

// Least-squares slope of log(error) against log(step): the measured order of convergence. Points with a
// non-finite or non-positive error are left out; NaN when fewer than two remain.
double fit_order(std::span<const double> steps, std::span<const double> errors);

// RMS distance over the free (unpinned) particles between two position sets, m.
Real rms_distance(const Model& model, std::span<const Vec3> a, std::span<const Vec3> b);

}  // namespace clothsim::cli
