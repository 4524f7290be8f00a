// The CI gate's workload (docs/performance.md): each kernel once on the fixed 64 x 64 sheet at one thread, each inside
// its own callgrind collection window and dumped under the kernel's name. Run by bench/gate under
// `valgrind --tool=callgrind --collect-atstart=no`; outside valgrind the client requests do nothing.
#include <tbb/global_control.h>
#include <valgrind/callgrind.h>

#include <cstdio>
#include <string>

#include "core/csr.h"
#include "io/obj_writer.h"
#include "systems/normals.h"
#include "systems/spring_forces.h"
#include "systems/step.h"
#include "tests/support/sheet_scene.h"

using namespace clothsim;

namespace {

// Counts the instructions of `body` alone and dumps them as "gate <name>".
template <class Body>
void measure(const char* name, Body&& body) {
  CALLGRIND_ZERO_STATS;
  CALLGRIND_TOGGLE_COLLECT;
  body();
  CALLGRIND_TOGGLE_COLLECT;
  const std::string label = std::string("gate ") + name;
  CALLGRIND_DUMP_STATS_AT(label.c_str());
}

}  // namespace

int main() {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  constexpr int n = 64;
  BuiltScene sym = bench::build_sheet(n, Integrator::symplectic);
  build_particle_springs(sym.model);  // the gather and two_phase kernels are gated on this blocked model too
  BuiltScene rk4 = bench::build_sheet(n, Integrator::rk4);
  // The implicit step at the peer's 1/48 s with its default, multigrid-preconditioned CG (to 1e-6).
  BuiltScene imp = bench::build_sheet(n, Integrator::implicit, 1.0 / 48);
  const Model& m = sym.model;
  Workspace ws = make_workspace(m, sym.options), ws_rk4 = make_workspace(rk4.model, rk4.options);
  Workspace ws_imp = make_workspace(imp.model, imp.options);
  State scratch = sym.state, scratch_rk4 = rk4.state, scratch_imp = imp.state;
  std::vector<Vec3> per_spring(m.spring_count);
  // Warm-up outside the windows: a few steps so the sheet is strained, and TBB's arena is started.
  for (int k = 0; k < 5; ++k) {
    step(m, sym.options, sym.state, scratch, ws, sym.options.dt);
    std::swap(sym.state, scratch);
  }
  rk4.state = sym.state;
  for (int k = 0; k < 5; ++k) {  // the implicit sheet falls for 0.1 s: its springs stretch, CG has work
    step(imp.model, imp.options, imp.state, scratch_imp, ws_imp, imp.options.dt);
    std::swap(imp.state, scratch_imp);
  }

  std::size_t sink = 0;
  measure("springs_gather", [&] { eval_springs_gather(m, sym.state.x, sym.state.v, ws.f); });
  measure("springs_blocked", [&] { eval_springs_blocked(m, sym.state.x, sym.state.v, ws.f); });
  measure("springs_two_phase", [&] { eval_springs_two_phase(m, sym.state.x, sym.state.v, ws.f, per_spring); });
  measure("step_symplectic", [&] { step(m, sym.options, sym.state, scratch, ws, sym.options.dt); });
  measure("step_rk4", [&] { step(rk4.model, rk4.options, rk4.state, scratch_rk4, ws_rk4, rk4.options.dt); });
  measure("step_implicit", [&] { step(imp.model, imp.options, imp.state, scratch_imp, ws_imp, imp.options.dt); });
  measure("normals", [&] { eval_normals(m, sym.state.x, ws.normal); });
  measure("obj_frame", [&] { sink += io::format_frame(m, m.cloths[0], "sheet", sym.state.x, ws.normal, 1).size(); });
  std::printf("gate workload done (%zu bytes of OBJ)\n", sink);
  return 0;
}
