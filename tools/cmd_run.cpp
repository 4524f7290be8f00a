// clothsim run SCENE.xml: simulate and write one OBJ per cloth and frame.
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <set>
#include <string>

#include "core/blas_kernel.h"
#include "core/cholesky_factor.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "io/mtl_writer.h"
#include "io/obj_writer.h"
#include "io/stats_json.h"
#include "sim/load_scene.h"
#include "sim/simulation.h"
#include "systems/collision/collision_check.h"
#include "systems/normals.h"
#include "tools/cli_args.h"
#include "tools/commands.h"
#include "tools/progress.h"
#include "tools/run_checkpoints.h"
#include "tools/run_outputs.h"

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

FrameRange parse_frames(const std::string& text, const SimOptions& m) {
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

// The independent checks of a frame: distances, vertices inside (closed colliders), cloth triangles crossing an
// open collider mesh, crossing cloth triangles.
void add_collision_checks(const Model& model, const State& state, Workspace& ws, io::FrameStats& f) {
  f.penetrations = count_intersecting_triangles(model, state.x);
  for (Index c = 0; c < Index(model.collision.colliders.size()); ++c) {
    f.collider_distance.push_back(min_collider_distance(model, state.x, ws.collision, c));
    // Each check counts where it is defined: inside for closed shapes, crossings for open meshes.
    f.penetrations += count_inside(model, state.x, ws.collision, c) +
                      count_collider_crossings(model, state.x, ws.collision, c);
  }
}

// What --stats writes of a frame.
io::FrameStats frame_stats(const sim::FrameReport& r) {
  io::FrameStats f;
  f.frame = r.frame;
  f.max_strain = r.max_strain;
  f.strain_excess = r.strain_excess;
  f.kinetic_energy = r.kinetic_energy;
  f.contacts = r.steps.counts.contacts;
  f.guarded = r.steps.counts.guarded;
  f.zones = r.steps.counts.zones;
  f.steps = {r.steps.taken, r.steps.rejected, r.steps.smallest, r.steps.largest};
  f.implicit_failed = r.steps.failed;
  for (const SolveRecord& solve : r.steps.solves) {
    f.cg_iterations.push_back(solve.cg_iterations);
    f.cg_residual.push_back(solve.cg_residual);
    f.factorizations += solve.factorizations;
  }
  return f;
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

  sim::LoadedScene loaded = sim::load_scene(args.positional[0]);
  sim::Simulation simulation(std::move(loaded.built), sim::ColliderTrack(loaded.desc));
  const Model& model = simulation.model();
  const SimOptions& options = simulation.options();
  const FrameRange frames = args.has("--frames") ? parse_frames(args.get("--frames"), options)
                                                 : FrameRange{options.start_frame, options.end_frame};

  const std::string out = args.get("--out"), stats_path = args.get("--stats");
  const std::vector<std::string> dirs = prepare_run_outputs(loaded.desc, args.has("--out") ? &out : nullptr,
                                                            args.has("--stats") ? &stats_path : nullptr);
  for (std::size_t c = 0; c < model.cloths.size(); ++c)
    io::write_material(dirs[c], model.cloths[c], loaded.desc.cloths[c].save_name);

  RunCheckpoints checkpoints(loaded.desc, loaded.inputs_fingerprint, model, options, simulation.state(), dirs.front(),
                             args.has("--checkpoint-every")
                                 ? parse_int("--checkpoint-every", args.get("--checkpoint-every"), 0)
                                 : loaded.desc.simulation.checkpoint_every,
                             frames.first);
  RunCheckpoints::Start start = checkpoints.start(args.has("--resume"), args.has("--quiet"));
  if (start.state) simulation.resume(std::move(*start.state), start.first_frame - 1, start.cholesky_renewal);

  Workspace& ws = simulation.workspace();
  io::RunStats stats;
  stats.scene = args.positional[0];
  stats.threads = threads;
  if (options.integrator == Integrator::implicit && options.solver.preconditioner == Preconditioner::cholesky) {
    stats.blas_kernel = blas_kernel_name();
    const bool user_chose = std::getenv("OPENBLAS_CORETYPE") && !std::getenv("CLOTHSIM_CHOSE_OPENBLAS_CORETYPE");
    stats.blas_kernel_chosen_by = !std::getenv("OPENBLAS_CORETYPE") ? "OpenBLAS"
                                  : user_chose                      ? "OPENBLAS_CORETYPE"
                                                                    : "clothsim";
    // main() sets the better kernels where it can; they are still older when its restart failed.
    const std::string coretype = better_openblas_coretype(stats.blas_kernel, cpu_vector_units());
    if (!coretype.empty() && !user_chose)
      std::fprintf(stderr,
                   "clothsim: warning: OpenBLAS runs its %s kernels on this CPU, older than its vector units; "
                   "OPENBLAS_CORETYPE=%s makes the Cholesky factorisation faster (docs/performance.md, "
                   "\"The BLAS kernels\")\n",
                   stats.blas_kernel.c_str(), coretype.c_str());
    if (ws.cholesky) stats.cholesky_pieces = int(cholesky_piece_count(*ws.cholesky));
    if (stats.cholesky_pieces > 1 && threads > 1 && !blas_calls_may_overlap())
      std::fprintf(stderr,
                   "clothsim: warning: the BLAS is OpenBLAS's single-threaded build, which cannot take calls from two "
                   "threads at once: the cloth's %d pieces are factored one after the other; Debian's "
                   "libopenblas0-pthread lets them be factored at once (docs/performance.md, \"Pieces factored at "
                   "once\")\n",
                   stats.cholesky_pieces);
  }
  stats.load_seconds = loaded.load_seconds;
  stats.topology_seconds = loaded.topology_seconds;
  stats.load_cpu_seconds = loaded.load_cpu_seconds;
  stats.topology_cpu_seconds = loaded.topology_cpu_seconds;
  Progress progress(frames.last - frames.first + 1, args.has("--quiet"));
  int status = exit_ok;

  while (simulation.next_frame() <= frames.last) {
    const sim::FrameReport report = simulation.advance_frame();
    const int frame = report.frame;
    if (report.diverged) {
      std::fprintf(stderr, "\nclothsim: error: %s\n", report.divergence.c_str());
      stats.status = "diverged";
      status = exit_diverged;
      break;
    }
    const State& state = simulation.state();
    stats.frames.push_back(frame_stats(report));
    if (model.collision.enabled && args.has("--stats")) add_collision_checks(model, state, ws, stats.frames.back());
    if (frame < frames.first) continue;
    const auto w0 = std::chrono::steady_clock::now();
    eval_normals(model, state.x, ws.normal);
    for (std::size_t c = 0; c < model.cloths.size(); ++c) {
      const ClothInfo& cloth = model.cloths[c];
      const std::string& save_name = loaded.desc.cloths[c].save_name;
      io::write_frame(io::frame_path(dirs[c], save_name, frame), model, cloth, save_name, state.x, ws.normal, frame);
    }
    stats.write_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    ++stats.frames_written;
    progress.frame_done(frame - frames.first + 1, frame);
    checkpoints.frame_written(frame, frames.last, state, simulation.workspace().cholesky_renewal);
  }
  progress.finish();
  const State& state = simulation.state();
  if (simulation.failed_steps() > 0)
    std::fprintf(stderr, "clothsim: warning: %lld of %lld steps failed their check and were kept; the first: %s\n",
                 static_cast<long long>(simulation.failed_steps()), static_cast<long long>(state.step),
                 simulation.first_failure().c_str());
  const std::string overrun = sim::describe_overrun(simulation.limit_overrun());
  if (!overrun.empty()) std::fprintf(stderr, "clothsim: warning: %s\n", overrun.c_str());

  stats.steps = state.step;
  const StepCounts& totals = simulation.totals();
  stats.force_evaluations = totals.force_evaluations;
  stats.cg_iterations = totals.cg_iterations;
  stats.implicit_failed_steps = simulation.failed_steps();
  stats.strain_limit_iterations = totals.strain_sweeps;
  stats.forces_seconds = totals.seconds_forces;
  stats.integrate_seconds = totals.seconds_integrate;
  stats.collide_seconds = totals.seconds_collide;
  stats.peak_rss_bytes = peak_rss_bytes();
  stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (args.has("--stats")) io::write_stats(args.get("--stats"), model, options, stats);
  return status;
}

}  // namespace clothsim::cli
