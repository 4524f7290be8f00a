// clothsim study scaling SCENE.xml --threads 1,2,4 [--weak]: runs the scene at each thread count under
// tbb::global_control, checks that every frame is byte-identical across counts (strong scaling), and writes
// CSV plus a gnuplot chart of speed-up and parallel efficiency (docs/performance.md). No thread count is built in.
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "sim/load_scene.h"
#include "sim/simulation.h"
#include "systems/diagnostics.h"
#include "tools/cli_args.h"
#include "tools/commands.h"
#include "tools/studies.h"

namespace clothsim::cli {
namespace {

const char* scaling_help =
    "usage: clothsim study scaling SCENE.xml --threads 1,2,4,... [--weak] [--frames N] [--repeat R] [--out DIR]\n"
    "  --threads LIST  thread counts to run, comma-separated (each >= 1)\n"
    "  --weak          weak scaling: every grid cloth grows with the thread count (particles ~ threads)\n"
    "  --frames N      frames to simulate per run (default: the scene's startFrame..endFrame)\n"
    "  --repeat R      runs per count; the median time is reported (default 1)\n"
    "  --out DIR       folder for scaling.csv, scaling.gp and scaling.svg (default: .)\n"
    "Strong scaling checks that positions and velocities after every frame are byte-identical at every count\n"
    "and fails (exit 1) when they are not. The chart needs gnuplot (tools/setup installs gnuplot-nox).";

std::vector<int> parse_thread_list(const std::string& text) {
  std::vector<int> counts;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) counts.push_back(parse_int("--threads", item, 1));
  if (counts.empty()) throw UsageError("--threads expects a list such as 1,2,4");
  return counts;
}

// Weak scaling: a grid of nx x ny vertices becomes about sqrt(t) times as many along each side at the same
// spacing (the sheet grows, so mass per particle and the stable step stay as they were), and each pin keeps
// its place on the sheet (corner pins stay at the corners).
SceneDesc grown_for_threads(const SceneDesc& desc, int threads) {
  SceneDesc out = desc;
  const double side = std::sqrt(double(threads));
  for (ClothDesc& c : out.cloths) {
    if (c.grid_nx == 0)
      throw Error(desc.path, c.line, "--weak grows grid cloths only; cloth '" + c.name + "' is a mesh");
    const int nx = c.grid_nx, ny = c.grid_ny;
    c.grid_nx = int(std::lround((nx - 1) * side)) + 1;
    c.grid_ny = int(std::lround((ny - 1) * side)) + 1;
    c.grid_w *= double(c.grid_nx - 1) / (nx - 1);
    c.grid_h *= double(c.grid_ny - 1) / (ny - 1);
    for (Index& p : c.pins) {
      const long i = std::lround(double(p % nx) * (c.grid_nx - 1) / (nx - 1));
      const long j = std::lround(double(p / nx) * (c.grid_ny - 1) / (ny - 1));
      p = Index(j * c.grid_nx + i);
    }
  }
  return out;
}

std::vector<MeshData> grid_meshes(const SceneDesc& desc) {
  std::vector<MeshData> meshes;
  for (const ClothDesc& c : desc.cloths) meshes.push_back(make_cloth_grid(c));
  return meshes;
}

// FNV-1a over the bytes of a state's positions and velocities, chained frame to frame.
std::uint64_t hash_state(std::uint64_t h, const State& s) {
  for (const auto* field : {&s.x, &s.v}) {
    const auto* p = reinterpret_cast<const unsigned char*>(field->data());
    for (std::size_t k = 0; k < field->size() * sizeof(Vec3); ++k) h = (h ^ p[k]) * 1099511628211ull;
  }
  return h;
}

struct RunResult {
  double seconds = 0;          // stepping only (hashing is outside)
  std::uint64_t hash = 14695981039346656037ull;
  bool diverged = false;
};

// `frames` frames through the run's frame loop; the clock covers the frames (steps and the divergence guard),
// not the hashing.
RunResult run_frames(const BuiltScene& built, const SceneDesc& desc, int frames) {
  sim::Simulation simulation(built, sim::ColliderTrack(desc));
  simulation.advance_frame();  // the start frame: the initial state, no step
  RunResult r;
  for (int f = 0; f < frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    const sim::FrameReport report = simulation.advance_frame();
    r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (report.diverged) { r.diverged = true; return r; }
    r.hash = hash_state(r.hash, simulation.state());
  }
  return r;
}

struct Row {
  int threads;
  Index particles;
  double seconds;
  std::uint64_t hash;
};

void write_chart(const std::filesystem::path& dir, bool weak) {
  std::string gp =
      "set datafile separator ','\n"
      "set terminal svg size 720,440\n"
      "set output '" + (dir / "scaling.svg").string() + "'\n"
      "set title '" + std::string(weak ? "weak" : "strong") + " scaling'\n"
      "set xlabel 'threads'\nset ylabel 'speed-up'\nset y2label 'parallel efficiency'\n"
      "set ytics nomirror\nset y2tics\nset y2range [0:1.2]\nset key left top\nset grid\n"
      "plot '" + (dir / "scaling.csv").string() + "' using 1:5 with linespoints title 'speed-up', "
      "'' using 1:1 with lines dashtype 2 title 'ideal', "
      "'' using 1:6 axes x1y2 with linespoints title 'efficiency'\n";
  io::write_file_atomic((dir / "scaling.gp").string(), gp);
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    std::fprintf(stderr, "clothsim study scaling: gnuplot not found; wrote %s only\n",
                 (dir / "scaling.gp").string().c_str());
    return;
  }
  const std::string cmd = "gnuplot '" + (dir / "scaling.gp").string() + "'";
  if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "clothsim study scaling: gnuplot failed on %s\n", cmd.c_str());
}

}  // namespace

int study_scaling(int argc, char** argv) {
  const Args args = parse_args(argc, argv, {"--threads", "--frames", "--repeat", "--out"}, {"--weak"});
  if (args.help) { std::puts(scaling_help); return exit_ok; }
  if (args.positional.size() != 1) throw UsageError("expected one scene file");
  if (!args.has("--threads")) throw UsageError("--threads is required, e.g. --threads 1,2,4");
  const std::vector<int> counts = parse_thread_list(args.get("--threads"));
  const bool weak = args.has("--weak");
  const int repeat = args.has("--repeat") ? parse_int("--repeat", args.get("--repeat"), 1) : 1;
  const std::filesystem::path dir = args.get("--out", ".");
  io::ensure_writable_dir(dir.string());

  sim::LoadedScene loaded = sim::load_scene(args.positional[0]);
  const SimOptions& base = loaded.built.options;
  const int frames = args.has("--frames") ? parse_int("--frames", args.get("--frames"), 1)
                                          : base.end_frame - base.start_frame;
  if (frames < 1) throw UsageError("the scene has no frame to simulate; give --frames N");

  std::vector<Row> rows;
  for (int t : counts) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, t);
    BuiltScene grown;
    if (weak) {
      const SceneDesc desc = grown_for_threads(loaded.desc, t);
      grown = build_model(desc, grid_meshes(desc));
    }
    const BuiltScene& built = weak ? grown : loaded.built;
    std::vector<double> times;
    RunResult r;
    for (int k = 0; k < repeat; ++k) {
      r = run_frames(built, loaded.desc, frames);
      if (r.diverged) {
        std::fprintf(stderr, "clothsim study scaling: the scene diverged at %d threads\n", t);
        return exit_diverged;
      }
      times.push_back(r.seconds);
    }
    std::sort(times.begin(), times.end());
    rows.push_back({t, built.model.particle_count, times[times.size() / 2], r.hash});
    std::fprintf(stderr, "threads %d: %.3f s\n", t, rows.back().seconds);
  }

  // Speed-up against the first count given (normally 1): strong T1/Tt; weak (work grows with t) t/t1 * T1/Tt.
  const Row& ref = rows.front();
  bool identical = true;
  std::string csv = "threads,particles,seconds,particle_steps_per_s,speedup,efficiency,identical\n";
  for (const Row& r : rows) {
    const double steps = double(frames) * base.steps_per_frame;
    const double rel = ref.seconds / r.seconds;
    const double speedup = weak ? rel * double(r.particles) / ref.particles : rel;
    const double efficiency = speedup / (double(r.threads) / ref.threads);
    const bool same = weak || r.hash == ref.hash;
    identical = identical && same;
    char line[256];
    std::snprintf(line, sizeof line, "%d,%d,%.6f,%.6g,%.4f,%.4f,%s\n", r.threads, r.particles, r.seconds,
                  steps * r.particles / r.seconds, speedup, efficiency, weak ? "n/a" : (same ? "yes" : "no"));
    csv += line;
  }
  io::write_file_atomic((dir / "scaling.csv").string(), csv);
  std::fputs(csv.c_str(), stdout);
  write_chart(dir, weak);
  if (!identical) {
    std::fprintf(stderr, "clothsim study scaling: frames differ between thread counts (determinism broken)\n");
    return 1;
  }
  return exit_ok;
}

}  // namespace clothsim::cli
