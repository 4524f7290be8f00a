// clothsim validate SCENE.xml: reads the scene and every mesh and builds the model, without simulating.
#include <cstdio>
#include <string>

#include "tools/cli_args.h"
#include "tools/commands.h"
#include "sim/load_scene.h"
#include "sim/step_advice.h"
#include "systems/auto_step.h"

namespace clothsim::cli {
namespace {

// Settings that parse but do not do what a user of the original tool expects (docs/scene-format.md, "Names
// from the original tool").
void print_setting_warnings(const SceneDesc& d, const Model& m) {
  if (d.simulation.integrator == Integrator::euler && m.air_damping == 0) {
    bool damped = false;
    for (Index k = 0; k < m.spring_count && !damped; ++k) damped = m.spring_kd[k] > 0;
    if (!damped)
      std::printf("  warning: integrator=\"euler\" without damping (spring damping and airDamping 0) grows every "
                  "oscillation at any time step; the original tool's \"Euler\" is integrator=\"symplectic\"\n");
  }
  if (!d.colliders.empty() && d.simulation.collision_iterations == 0)
    std::printf("  warning: collisionIterations=\"0\" turns collisions off: the %zu collider%s will be ignored\n",
                d.colliders.size(), d.colliders.size() == 1 ? "" : "s");
}

}  // namespace

int cmd_validate(int argc, char** argv) {
  const Args args = parse_args(argc, argv, {}, {});
  if (args.help) {
    std::puts("usage: clothsim validate SCENE.xml\n"
              "Checks that the scene parses, every file exists, meshes load and values are in range.");
    return exit_ok;
  }
  if (args.positional.size() != 1) throw UsageError("expected one scene file");
  const sim::LoadedScene s = sim::load_scene(args.positional[0]);
  const Model& m = s.built.model;
  const SimOptions& o = s.built.options;
  std::printf("%s: ok\n", args.positional[0].c_str());
  std::printf("  cloths %zu, particles %d, springs %d, triangles %d, pinned %zu (attached %zu), stitches %d\n",
              m.cloths.size(), m.particle_count, m.spring_count, m.tri_count, m.pinned.size(),
              m.attach_particle.size(), m.stitch_count);
  std::printf("  frames %d..%d at %g fps, %d steps per frame of %.6g s\n", o.start_frame, o.end_frame, o.fps,
              o.steps_per_frame, o.dt);
  // Whether each parameter stayed one scalar or became an array because a map was given (docs/maps.md).
  auto form = [](const ParamField& f) {
    if (f.uniform()) return std::string("one value");
    if (f.paletted()) return std::to_string(f.size()) + " values (mapped or scaled)";
    return std::string("per element (mapped or scaled)");
  };
  std::printf("  stiffness %s, damping %s, thickness %s\n", form(m.spring_ke).c_str(), form(m.spring_kd).c_str(),
              form(m.particle_thickness).c_str());
  // Stability limits of the springs with their damping, air damping and wind (docs/stability.md): power
  // iterations on M^-1 K and M^-1 C at rest.
  const StableSteps limits = model_stable_steps(m, s.built.state.x);
  char euler[32] = "none";
  if (limits.euler > 0) std::snprintf(euler, sizeof euler, "%.6g s", limits.euler);
  std::printf("  omega_max %.6g rad/s, damping rate up to %.6g 1/s; largest stable step: symplectic %.6g s, "
              "rk4 %.6g s, euler %s, implicit unlimited\n", limits.omega_max, limits.gamma_max, limits.symplectic,
              limits.rk4, euler);
  if (m.hinge_count > 0)
    std::printf("  dihedral bending: %ld hinges, in the implicit matrix; stepped explicitly by the other integrators: "
                "largest stable step %.6g s\n", long(m.hinge_count), limits.hinges);
  if (o.auto_step)
    std::printf("  timestep auto: %.6g s (stepSafety %g), at least %.6g s\n", o.dt, o.step_safety, o.min_dt);
  const std::string warning = sim::step_warning(o, limits);
  if (!warning.empty()) std::printf("  %s\n", warning.c_str());
  print_setting_warnings(s.desc, m);
  return exit_ok;
}

}  // namespace clothsim::cli
