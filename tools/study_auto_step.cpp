// clothsim study autostep: the step timestep="auto" chooses against the largest stable step (no divergence, no
// perturbation growing exponentially), found by bisection, on the given scenes and on the seeded family of
// io/scene_family.h.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/scene_family.h"
#include "sim/load_scene.h"
#include "systems/auto_step.h"
#include "systems/perturbation_growth.h"
#include "systems/stability.h"
#include "tools/cli_args.h"
#include "tools/commands.h"
#include "tools/studies.h"

namespace clothsim::cli {
namespace {

const char* auto_step_help =
    "usage: clothsim study autostep [SCENE.xml ...] [--family N] [--seconds T] [--out DIR]\n"
    "For each scene (and the first N scenes of the seeded family, default 24, written into DIR, default\n"
    "study-autostep), the step timestep=\"auto\" chooses and the largest fixed step in [auto, 16 auto] that runs\n"
    "T simulated seconds (default 0.25) without diverging as `clothsim run` judges it (non-finite, the energy\n"
    "past its bound or a spring torn within a frame) and without a perturbation growing exponentially faster than\n"
    "at half the step over the run's second half, by bisection to 1%. Where the theory's growth at 1.25x the\n"
    "estimated limit is too slow to show within T (explicit Euler on lightly damped modes), the run lasts until it\n"
    "would reach 10^4, at least 2 s. Every scene starts perturbed by up to 5e-5 m a coordinate, as round-off would\n"
    "in a long run (io/scene_family.h: a cloth at rest has no motion to amplify). Prints a Markdown table: auto,\n"
    "largest stable, their ratio, the largest stable over the estimated limit, the seconds each step ran.\n"
    "Implicit scenes have no stability limit and are skipped.";

struct Row {
  std::string name, integrator;
  Real auto_step = 0, largest = 0;  // largest < 0: even 16x auto ran; 0: auto itself diverged
  Real limit = 0;                   // the estimated stable step (stable_steps), s
  Real seconds = 0;                 // how long each step ran
};

// A step past a mode's limit can run without diverging: the unstable mode saturates into a vibration short of the
// energy bound and of a torn spring (a light corner of examples/fold at 30 m/s), so a step also fails when a
// perturbation grows exponentially faster than at half the step (growth_over_half_step: the physics' own growth,
// a swing, a contact, buckling, is the same at both steps and cancels). Past a symplectic or RK4 limit the mode
// grows fast (x4 a step at 1.25x the undamped symplectic limit) and shows within a short run; past explicit
// Euler's it grows by |1 + h lambda| = 1 + O((gamma/omega)^2) a step, gamma (r - 1) / 2 per second at r times the
// limit. So a scene runs until the theory's growth at 1.25x the probes' limit reaches 10^4, at least T, and at
// least 2 s where that is longer than T.
constexpr int growth_windows = 8;
constexpr Real probe_ratio = 1.25, probe_growth = 1e4;
constexpr Real shortest_growth_run = 2, longest_run = 30;  // s

// Seconds the run must last for the theory's growth at probe_ratio x the two probes' limit to reach probe_growth
// (explicit Euler's floor, where it sets the scene's limit, belongs to a mode the probes do not give).
Real onset_seconds(const Model& model, Integrator integrator, std::span<const Vec3> x) {
  const DampedModes d = estimate_modes(model, x);
  const Real h = probe_ratio * std::min(mode_step_limit(integrator, d.omega_max, d.gamma_of_stiff),
                                        mode_step_limit(integrator, d.omega_of_damped, d.gamma_max));
  if (!std::isfinite(h) || !(h > 0)) return 0;
  const Real rho = std::max(mode_amplification(integrator, d.omega_max, d.gamma_of_stiff, h),
                            mode_amplification(integrator, d.omega_of_damped, d.gamma_max, h));
  return rho > 1 ? std::log(probe_growth) * h / std::log(rho) : 0;
}

Row study_scene(const std::string& name, const Model& model, const SimOptions& options, const State& start,
                Real seconds) {
  Row row{name, integrator_name(options.integrator)};
  SimOptions automatic = options;
  automatic.auto_step = true;
  choose_auto_step(model, automatic, start.x, name);
  row.auto_step = automatic.dt;
  row.limit = stable_step_limit(model_stable_steps(model, start.x), options.integrator);
  const Real onset = onset_seconds(model, options.integrator, start.x);
  row.seconds = onset > seconds ? std::clamp(onset, shortest_growth_run, longest_run) : seconds;
  auto stable = [&](Real h) {
    const std::int64_t steps = std::int64_t(std::ceil(row.seconds / h));
    return !run_diverges(model, options, start, h, steps) &&
           !grows_exponentially(growth_over_half_step(model, options, start, h, steps, growth_windows));
  };
  if (!stable(row.auto_step)) return row;
  Real lo = row.auto_step, hi = 16 * row.auto_step;
  if (stable(hi)) { row.largest = -1; return row; }
  while (hi / lo > 1.01) {
    const Real mid = std::sqrt(lo * hi);
    (stable(mid) ? lo : hi) = mid;
  }
  row.largest = lo;
  return row;
}

}  // namespace

int study_auto_step(int argc, char** argv) {
  const Args args = parse_args(argc, argv, {"--family", "--seconds", "--out"}, {});
  if (args.help) { std::puts(auto_step_help); return exit_ok; }
  const int family = args.has("--family") ? parse_int("--family", args.get("--family"), 0) : 24;
  const Real seconds = args.has("--seconds") ? std::stod(args.get("--seconds")) : 0.25;
  const std::filesystem::path out = args.has("--out") ? args.get("--out") : "study-autostep";
  std::vector<std::string> scenes = args.positional;
  std::filesystem::create_directories(out);
  for (int seed = 0; seed < family; ++seed) {
    const std::filesystem::path path = out / ("family_" + std::to_string(seed) + ".xml");
    io::write_file_atomic(path.string(), io::family_scene(seed).xml);
    scenes.push_back(path.string());
  }
  std::puts("| scene | integrator | auto step, s | largest stable step, s | largest / auto | largest / estimate | run, s |\n"
            "|---|---|---|---|---|---|---|");
  int outside = 0;
  for (const std::string& path : scenes) {
    sim::LoadedScene loaded = sim::load_scene(path);
    if (loaded.built.options.integrator == Integrator::implicit) continue;
    io::perturb_start(loaded.built.model, loaded.built.state, 1e-4);
    const Row r = study_scene(std::filesystem::path(path).filename().string(), loaded.built.model,
                              loaded.built.options, loaded.built.state, seconds);
    char largest[32], ratio[32], to_limit[32] = "-";
    if (r.largest < 0) { std::snprintf(largest, sizeof largest, "> %.4g", 16 * r.auto_step); std::snprintf(ratio, sizeof ratio, "> 16"); }
    else if (r.largest == 0) { std::snprintf(largest, sizeof largest, "auto diverged"); std::snprintf(ratio, sizeof ratio, "< 1"); }
    else {
      std::snprintf(largest, sizeof largest, "%.4g", r.largest);
      std::snprintf(ratio, sizeof ratio, "%.2f", r.largest / r.auto_step);
      std::snprintf(to_limit, sizeof to_limit, "%.3f", r.largest / r.limit);
    }
    if (!(r.largest > 0) || r.largest > 2 * r.auto_step) ++outside;
    std::printf("| %s | %s | %.4g | %s | %s | %s | %.3g |\n", r.name.c_str(), r.integrator.c_str(), r.auto_step,
                largest, ratio, to_limit, r.seconds);
    std::fflush(stdout);
  }
  std::printf("\n%d scene(s) where auto is above the largest stable step or below half of it\n", outside);
  return exit_ok;
}

}  // namespace clothsim::cli
