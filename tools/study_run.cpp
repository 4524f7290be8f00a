#include "tools/study_run.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>
#include <utility>
#include <vector>

#include "core/csr.h"
#include "io/atomic_file.h"
#include "systems/diagnostics.h"
#include "systems/step.h"
#include "tools/cli_args.h"
#include "sim/cpu_clock.h"

namespace clothsim::cli {

StudyOptions parse_study_options(int argc, char** argv, const std::string& default_out) {
  const Args args = parse_args(argc, argv, {"--out"}, {"--quick"});
  StudyOptions o{args.get("--out", default_out), args.has("--quick"), args.help};
  if (o.help) return o;
  if (!args.positional.empty()) throw UsageError("unexpected argument '" + args.positional[0] + "'");
  io::ensure_writable_dir(o.out);
  return o;
}

std::string csv_number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  if (!std::isfinite(v)) return "nan";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

void run_tasks_in_parallel(std::size_t count, const std::function<void(std::size_t)>& task) {
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next++; i < count; i = next++) task(i);
  };
  const std::size_t threads = std::min<std::size_t>(count, std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
}

TimedRun timed_run(const Model& base, const State& initial, Integrator integrator, Real h, std::int64_t steps,
                   int repeats, double repeat_below) {
  Model model = base;
  ensure_particle_springs(model, integrator);
  SimOptions options;  // the default solver settings
  options.integrator = integrator;
  Workspace ws = make_workspace(model, options);
  TimedRun best;
  for (int r = 0; r < repeats; ++r) {
    State state = initial, scratch = initial;
    std::int64_t evaluations = 0;
    const double t0 = sim::thread_cpu_seconds();
    std::int64_t k = 0;
    bool finite = true;
    for (; k < steps; ++k) {
      evaluations += step(model, options, state, scratch, ws, h).counts.force_evaluations;
      std::swap(state, scratch);
      // A diverging run is cut short; checked sparsely so the check costs nothing measurable.
      if ((k & 1023) == 1023 && !(finite = state_is_finite(state))) { ++k; break; }
    }
    const double seconds = sim::thread_cpu_seconds() - t0;
    finite = finite && state_is_finite(state);
    if (r == 0 || seconds < best.cpu_seconds) {
      best.state = std::move(state);
      best.cpu_seconds = seconds;
      best.force_evaluations = evaluations;
      best.steps = k;
      best.finite = finite;
    }
    if (seconds >= repeat_below || !finite) break;
  }
  return best;
}

double fit_order(std::span<const double> steps, std::span<const double> errors) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (!(std::isfinite(errors[i]) && errors[i] > 0)) continue;
    const double x = std::log(steps[i]), y = std::log(errors[i]);
    n += 1; sx += x; sy += y; sxx += x * x; sxy += x * y;
  }
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

Real rms_distance(const Model& model, std::span<const Vec3> a, std::span<const Vec3> b) {
  Real sum = 0;
  Index count = 0;
  for (Index i = 0; i < model.particle_count; ++i) {
    if (model.particle_inv_mass[i] == 0) continue;
    sum += (a[i] - b[i]).squaredNorm();
    ++count;
  }
  return std::sqrt(sum / Real(std::max<Index>(count, 1)));
}

}  // namespace clothsim::cli
