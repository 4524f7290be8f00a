// clothsim run SCENE.xml: simulate and write one OBJ per cloth and frame.
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <set>
#include <string>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/mtl_writer.h"
#include "io/obj_writer.h"
#include "io/stats_json.h"
#include "systems/adaptive_step.h"
#include "systems/collision/collision_check.h"
#include "systems/diagnostics.h"
#include "systems/normals.h"
#include "systems/spring_forces.h"
#include "systems/stability.h"
#include "systems/step.h"
#include "tools/cli_args.h"
#include "tools/commands.h"
#include "tools/progress.h"
#include "tools/run_checkpoints.h"
#include "tools/run_outputs.h"
#include "tools/scene_loader.h"
#include "tools/step_advice.h"

namespace clothsim::cli {
namespace {

const char* run_help =
    "usage: clothsim run SCENE.xml [--out DIR] [--threads N] [--frames A:B] [--stats FILE.json] [--quiet]\n"
    "  --out DIR          write every cloth's frames into DIR instead of its saveDir\n"
    "  --threads N        worker threads (default: all cores); output is identical for any N\n"
    "  --frames A:B       write frames A..B only (simulation still starts at the scene's startFrame)\n"
    "  --stats FILE.json  counts, timings by phase (wall; CPU too for load and topology), peak memory,\n"
    "                     per-frame strain and kinetic energy\n"
    "                     (with collisions: contacts, cloth-collider distances, penetrations)\n"
    "  --quiet            no progress on stderr\n"
    "  --checkpoint-every K  checkpoint every K frames and at the end (default: the scene's checkpointEvery)\n"
    "  --resume           continue from the newest valid checkpoint; later frames are recomputed identically\n"
    "Exit codes: 0 done, 2 bad input (file, line and what was expected on stderr), 3 diverged (non-finite\n"
    "values, or the mechanical energy rose past the bound of docs/stability.md; no such frame is written).";

struct FrameRange {
  int first, last;
};

FrameRange parse_frames(const std::string& text, const Model& m) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw UsageError("--frames expects A:B, got '" + text + "'");
  FrameRange r{parse_int("--frames", text.substr(0, colon), 0), parse_int("--frames", text.substr(colon + 1), 0)};
  if (r.first > r.last || r.first < m.start_frame || r.last > m.end_frame)
    throw UsageError("--frames " + text + " must satisfy " + std::to_string(m.start_frame) + " <= A <= B <= " +
                     std::to_string(m.end_frame) + " (the scene's startFrame..endFrame)");
  return r;
}

long long peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<long long>(u.ru_maxrss) * 1024;
}

// Contacts of the frame's steps, and the independent checks: distances, vertices inside (closed colliders),
// cloth triangles crossing an open collider mesh, crossing cloth triangles.
void add_collision_stats(const Model& model, const State& state, Workspace& ws, io::FrameStats& f) {
  f.contacts = ws.collision.contacts_found;
  ws.collision.contacts_found = 0;
  f.zones = ws.collision.zones.figures;
  ws.collision.zones.figures = {};
  f.penetrations = count_intersecting_triangles(model, state.x);
  for (Index c = 0; c < Index(model.collision.colliders.size()); ++c) {
    f.collider_distance.push_back(min_collider_distance(model, state.x, ws.collision, c));
    // Each check counts where it is defined: inside for closed shapes, crossings for open meshes.
    f.penetrations += count_inside(model, state.x, ws.collision, c) +
                      count_collider_crossings(model, state.x, ws.collision, c);
  }
}

// Why an implicit step failed its health check (Workspace::SolveRecord::failed), in words, with the remedy.
std::string implicit_failure(const Model& model, const Workspace::SolveRecord& r, int frame) {
  char text[400];
  if (!r.converged)
    std::snprintf(text, sizeof text, "frame %d: CG stopped at relative residual %.3g above cgTolerance %.3g "
                  "(cgMaxIterations %d): raise cgMaxIterations or use preconditioner=\"cholesky\"", frame,
                  r.cg_residual, model.cg_tolerance, model.cg_max_iterations);
  else if (r.newton_diverged)
    std::snprintf(text, sizeof text, "frame %d: a Newton correction raised the backward-Euler residual: take a "
                  "smaller timestep", frame);
  else
    std::snprintf(text, sizeof text, "frame %d: the largest spring strain went from %.3g to %.3g in one step of "
                  "%.3g s, past the %.2g a step that a linearised implicit step can be trusted with: take a "
                  "smaller timestep or more newtonIterations", frame, r.strain_before, r.strain_after, model.dt,
                  Workspace::SolveRecord::strain_jump);
  return text;
}

}  // namespace

int cmd_run(int argc, char** argv) {
  const auto wall0 = std::chrono::steady_clock::now();
  const Args args = parse_args(argc, argv, {"--out", "--threads", "--frames", "--stats", "--checkpoint-every"},
                               {"--quiet", "--resume"});
  if (args.help) { std::puts(run_help); return exit_ok; }
  if (args.positional.size() != 1) throw UsageError("expected one scene file");
  const int threads = args.has("--threads") ? parse_int("--threads", args.get("--threads"), 1)
                                            : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);

  LoadedScene loaded = load_scene(args.positional[0]);
  const Model& model = loaded.built.model;
  State state = std::move(loaded.built.state);
  const FrameRange frames = args.has("--frames") ? parse_frames(args.get("--frames"), model)
                                                 : FrameRange{model.start_frame, model.end_frame};

  const std::string out = args.get("--out"), stats_path = args.get("--stats");
  const std::vector<std::string> dirs = prepare_run_outputs(args.positional[0], model, args.has("--out") ? &out : nullptr,
                                                            args.has("--stats") ? &stats_path : nullptr);
  for (std::size_t c = 0; c < model.cloths.size(); ++c) io::write_material(dirs[c], model.cloths[c]);

  // Divergence guard (docs/stability.md): every frame is checked before it is written. Energies are measured from
  // the scene's initial state, taken before a --resume replaces it, so a resumed run is judged like a whole one.
  const std::vector<Vec3> x_start = state.x;
  const Real energy_start = mechanical_energy(model, state, x_start);
  const Real energy_bound = energy_rise_bound(model, x_start);
  // timestep="auto": steps adapt inside the frame (systems/adaptive_step.h); it stops only below minTimestep.
  AdaptiveStepper stepper(model, state);

  RunCheckpoints checkpoints(loaded.desc, loaded.inputs_fingerprint, model, state, dirs.front(),
                             args.has("--checkpoint-every")
                                 ? parse_int("--checkpoint-every", args.get("--checkpoint-every"), 0)
                                 : loaded.desc.simulation.checkpoint_every,
                             frames.first);
  const int first_frame = checkpoints.start(args.has("--resume"), state, args.has("--quiet"));

  Workspace ws = make_workspace(model);
  State scratch = state;
  io::RunStats stats;
  stats.scene = args.positional[0];
  stats.threads = threads;
  stats.load_seconds = loaded.load_seconds;
  stats.topology_seconds = loaded.topology_seconds;
  stats.load_cpu_seconds = loaded.load_cpu_seconds;
  stats.topology_cpu_seconds = loaded.topology_cpu_seconds;
  Progress progress(frames.last - frames.first + 1, args.has("--quiet"));
  int status = exit_ok;
  std::string first_failure;  // the first implicit step whose health check failed, in words

  for (int frame = first_frame; frame <= frames.last; ++frame) {
    ws.solve_log.clear();
    FrameSteps steps{frame > model.start_frame ? model.steps_per_frame : 0, 0, model.dt, model.dt};
    bool stepped = true;
    if (frame > model.start_frame && model.auto_step) stepped = stepper.advance_frame(model, state, scratch, ws, steps);
    else if (frame > model.start_frame) step_frame(model, state, scratch, ws);
    const bool finite = state_is_finite(state);
    const Real energy_rise = finite ? mechanical_energy(model, state, x_start) - energy_start : 0;
    if (!stepped || !finite || !(energy_rise <= energy_bound)) {
      char reason[200];
      if (!stepped)
        std::snprintf(reason, sizeof reason, "a step below minTimestep %.3g s was rejected: %s", model.min_dt,
                      verdict_name(stepper.last_rejection()));
      else if (finite)
        std::snprintf(reason, sizeof reason, "the mechanical energy rose by %.3g J, past the bound %.3g J",
                      energy_rise, energy_bound);
      else
        std::snprintf(reason, sizeof reason, "non-finite positions or velocities");
      const Real failed_step = model.auto_step ? stepper.current_step(model) : model.dt;
      const std::string remedy = step_remedy(model, scene_stable_steps(model, x_start), failed_step);
      std::fprintf(stderr,
                   "\nclothsim: error: frame %d, step %lld: the simulation diverged (%s); no frame from here on "
                   "was written. The step was %.3g s: %s.\n",
                   frame, static_cast<long long>(state.step), reason, failed_step, remedy.c_str());
      stats.status = "diverged";
      status = exit_diverged;
      break;
    }
    stats.frames.push_back({frame, max_spring_strain(model, state.x), kinetic_energy(model, state.v), 0, {}, 0, {}, {}, {}});
    stats.frames.back().steps = {steps.taken, steps.rejected, steps.smallest, steps.largest};
    if (model.collision.enabled && args.has("--stats")) add_collision_stats(model, state, ws, stats.frames.back());
    for (const Workspace::SolveRecord& r : ws.solve_log) {
      stats.frames.back().cg_iterations.push_back(r.cg_iterations);
      stats.frames.back().cg_residual.push_back(r.cg_residual);
      stats.frames.back().implicit_failed += r.failed() ? 1 : 0;
      stats.frames.back().factorizations += r.factorizations;
      if (r.failed() && first_failure.empty()) first_failure = implicit_failure(model, r, frame);
    }
    if (frame < frames.first) continue;
    const auto w0 = std::chrono::steady_clock::now();
    eval_normals(model, state.x, ws.normal);
    for (std::size_t c = 0; c < model.cloths.size(); ++c) {
      const ClothInfo& cloth = model.cloths[c];
      io::write_frame(io::frame_path(dirs[c], cloth.save_name, frame), model, cloth, state.x, ws.normal, frame);
    }
    stats.write_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    ++stats.frames_written;
    progress.frame_done(frame - frames.first + 1, frame);
    checkpoints.frame_written(frame, frames.last, state);
  }
  progress.finish();
  if (ws.implicit_failed_total > 0)
    std::fprintf(stderr, "clothsim: warning: %lld of %lld implicit steps failed their health check; the first: %s\n",
                 ws.implicit_failed_total, static_cast<long long>(state.step), first_failure.c_str());

  stats.steps = state.step;
  stats.force_evaluations = ws.force_evaluations;
  stats.cg_iterations = ws.cg_iterations_total;
  stats.implicit_failed_steps = ws.implicit_failed_total;
  stats.strain_limit_iterations = ws.strain_iterations_total;
  stats.forces_seconds = ws.seconds_forces;
  stats.integrate_seconds = ws.seconds_integrate;
  stats.collide_seconds = ws.seconds_collide;
  stats.peak_rss_bytes = peak_rss_bytes();
  stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (args.has("--stats")) io::write_stats(args.get("--stats"), model, stats);
  return status;
}

}  // namespace clothsim::cli
