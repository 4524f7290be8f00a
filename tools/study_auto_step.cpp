// clothsim study autostep: the step timestep="auto" chooses against the largest step that runs without
// divergence, found by bisection, on the given scenes and on the seeded family of io/scene_family.h.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/scene_family.h"
#include "sim/load_scene.h"
#include "systems/auto_step.h"
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
    "T simulated seconds (default 0.25) without diverging as `clothsim run` judges it (non-finite or the energy\n"
    "past its bound), by bisection to 1%. Every scene starts perturbed by up to 5e-5 m a coordinate, as round-off\n"
    "would in a long run (io/scene_family.h: a cloth at rest has no motion to amplify). Prints a\n"
    "Markdown table: auto, largest stable, their ratio. Implicit scenes have no stability limit and are skipped.";

struct Row {
  std::string name, integrator;
  Real auto_step = 0, largest = 0;  // largest < 0: even 16x auto ran; 0: auto itself diverged
};

Row study_scene(const std::string& name, const Model& model, const SimOptions& options, const State& start,
                Real seconds) {
  Row row{name, integrator_name(options.integrator)};
  SimOptions automatic = options;
  automatic.auto_step = true;
  choose_auto_step(model, automatic, start.x, name);
  row.auto_step = automatic.dt;
  auto stable = [&](Real h) { return !run_diverges(model, options, start, h, std::int64_t(std::ceil(seconds / h))); };
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
  std::puts("| scene | integrator | auto step, s | largest stable step, s | largest / auto |\n|---|---|---|---|---|");
  int outside = 0;
  for (const std::string& path : scenes) {
    sim::LoadedScene loaded = sim::load_scene(path);
    if (loaded.built.options.integrator == Integrator::implicit) continue;
    io::perturb_start(loaded.built.model, loaded.built.state, 1e-4);
    const Row r = study_scene(std::filesystem::path(path).filename().string(), loaded.built.model,
                              loaded.built.options, loaded.built.state, seconds);
    char largest[32], ratio[32];
    if (r.largest < 0) { std::snprintf(largest, sizeof largest, "> %.4g", 16 * r.auto_step); std::snprintf(ratio, sizeof ratio, "> 16"); }
    else if (r.largest == 0) { std::snprintf(largest, sizeof largest, "auto diverged"); std::snprintf(ratio, sizeof ratio, "< 1"); }
    else { std::snprintf(largest, sizeof largest, "%.4g", r.largest); std::snprintf(ratio, sizeof ratio, "%.2f", r.largest / r.auto_step); }
    if (!(r.largest > 0) || r.largest > 2 * r.auto_step) ++outside;
    std::printf("| %s | %s | %.4g | %s | %s |\n", r.name.c_str(), r.integrator.c_str(), r.auto_step, largest, ratio);
    std::fflush(stdout);
  }
  std::printf("\n%d scene(s) where auto is above the largest stable step or below half of it\n", outside);
  return exit_ok;
}

}  // namespace clothsim::cli
