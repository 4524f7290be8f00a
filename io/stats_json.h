#pragma once
// The --stats file of `clothsim run`: counts, timings by phase, peak memory and per-frame diagnostics.
#include <string>
#include <vector>

#include "core/model.h"

namespace clothsim::io {

struct FrameStats {
  int frame = 0;
  Real max_strain = 0;      // largest (|d| - rest)/rest over all springs
  Real strain_excess = 0;   // maxStrain scenes: largest (|d| - rest)/rest - maxStrain over the limited springs
  Real kinetic_energy = 0;  // J
  // Collisions (written only when the scene has colliders or self-collision):
  long long contacts = 0;                 // contacts found in the first collision pass of this frame's steps
  std::vector<Real> collider_distance;    // smallest cloth-to-collider distance, m (one per collider)
  long long penetrations = 0;             // independent check: vertices inside colliders + crossing triangle pairs
  long long guarded = 0;  // vertices the collider guard put back on a surface (strain-limited scenes with collisions)
  std::vector<int> cg_iterations;  // implicit: CG iterations of each step of the frame (empty otherwise)
  std::vector<Real> cg_residual;   // implicit: final relative CG residual |r|/|b| of each step
  ZoneFigures zones;               // rigid impact zones of this frame's steps (written when the scene has them)
  int implicit_failed = 0;         // implicit: steps of the frame whose health check failed (SolveRecord::failed)
  int factorizations = 0;          // implicit, preconditioner="cholesky": numeric factorisations in the frame
  struct Steps {
    int taken = 0, rejected = 0;   // steps of the frame; rejected ones were retried smaller (timestep="auto")
    Real smallest = 0, largest = 0;  // s, accepted steps
  } steps;
};

struct RunStats {
  std::string scene;
  int threads = 0;
  std::string blas_kernel;  // OpenBLAS's kernels, when the Cholesky preconditioner runs (core/blas_kernel.h)
  std::string blas_kernel_chosen_by;  // "OpenBLAS", "clothsim" (tools/main.cpp) or "OPENBLAS_CORETYPE" (the user)
  int cholesky_pieces = 0;  // the Cholesky factor's pieces (core/cholesky_factor.h), when it runs
  long long steps = 0;
  int frames_written = 0;
  double wall_seconds = 0;
  double load_seconds = 0, topology_seconds = 0, forces_seconds = 0, integrate_seconds = 0, write_seconds = 0;
  double collide_seconds = 0;
  double load_cpu_seconds = 0, topology_cpu_seconds = 0;  // process CPU time (all threads) of those phases
  long long force_evaluations = 0;
  long long cg_iterations = 0;            // implicit: over the whole run
  long long implicit_failed_steps = 0;    // implicit: steps whose health check failed, over the whole run
  long long strain_limit_iterations = 0;  // strain-limit Jacobi sweeps over the whole run
  long long peak_rss_bytes = 0;
  std::string status = "ok";  // ok | diverged
  std::vector<FrameStats> frames;
};

std::string format_stats(const Model& model, const SimOptions& options, const RunStats& stats);
void write_stats(const std::string& path, const Model& model, const SimOptions& options, const RunStats& stats);

}  // namespace clothsim::io
