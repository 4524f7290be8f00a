// Peer side by side (docs/performance.md): the same 128 x 128 sheet (1 m, 1 kg, hanging from two corners) for the same
// simulated time in clothsim and in Bullet's soft bodies (btSoftBodyHelpers::CreatePatch), in one process.
// Prints, for each: the step, simulated seconds per wall second and per CPU second (all threads; what a loaded
// machine cannot inflate), particle-steps per second, the largest strain seen (sampled every 10 steps) and
// clothsim's rate over the peer's (cs_vs_peer: above 1 where clothsim simulates faster). docs/performance.md explains the model differences.
//
// Usage: clothsim_peer_bullet [seconds=1] [clothsim_dt=5e-5] [stiffness=3000] [bullet_dt=1/240] [iterations=4]
//                             [integrator=symplectic|implicit|rk4] [threads=2] [cg_tolerance=1e-6]
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <tbb/global_control.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "systems/spring_forces.h"
#include "systems/step.h"
#include "tests/support/sheet_scene.h"

using namespace clothsim;

namespace {

constexpr int side = 128;

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct PeerResult {
  double dt = 0, wall = 0, cpu = 0, max_strain = 0;
  long steps = 0;
  bool finite = true;
};

PeerResult run_clothsim(double seconds, double dt, double stiffness, Integrator integrator, double cg_tolerance) {
  SceneDesc desc = bench::sheet_scene(side, integrator, dt);
  desc.simulation.cg_tolerance = cg_tolerance;
  desc.cloths[0].stiffness = stiffness;
  BuiltScene b = build_model(desc, {make_cloth_grid(desc.cloths[0])});
  const Model& m = b.model;
  Workspace ws = make_workspace(m, b.options);
  State scratch = b.state;
  PeerResult r;
  r.dt = dt;
  r.steps = std::lround(seconds / dt);
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = process_cpu_seconds();
  for (long k = 0; k < r.steps; ++k) {
    step(m, b.options, b.state, scratch, ws, dt);
    std::swap(b.state, scratch);
    if (k % 10 == 9) r.max_strain = std::max(r.max_strain, max_spring_strain(m, b.state.x));
  }
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu = process_cpu_seconds() - c0;
  r.finite = std::isfinite(b.state.x[side * side / 2][1]);
  return r;
}

// Bullet's position-based cloth: structural and shear links from CreatePatch, bending links two apart (as
// clothsim's flex springs), linear stiffness 1, `iterations` position iterations per step, no collisions.
PeerResult run_bullet(double seconds, double dt, int iterations) {
  btSoftBodyRigidBodyCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, -9.81, 0));
  btSoftBodyWorldInfo& info = world.getWorldInfo();
  info.m_gravity = btVector3(0, -9.81, 0);
  info.m_sparsesdf.Initialize();
  btSoftBody* cloth = btSoftBodyHelpers::CreatePatch(info, btVector3(-0.5, 1, -0.5), btVector3(0.5, 1, -0.5),
                                                     btVector3(-0.5, 1, 0.5), btVector3(0.5, 1, 0.5), side, side,
                                                     1 | 2, true);
  cloth->generateBendingConstraints(2, cloth->m_materials[0]);
  cloth->m_cfg.piterations = iterations;
  cloth->m_cfg.collisions = 0;
  cloth->setTotalMass(1);
  world.addSoftBody(cloth);

  PeerResult r;
  r.dt = dt;
  r.steps = std::lround(seconds / dt);
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = process_cpu_seconds();
  for (long k = 0; k < r.steps; ++k) {
    world.stepSimulation(btScalar(dt), 0);
    if (k % 10 == 9)
      for (int l = 0; l < cloth->m_links.size(); ++l) {
        const btSoftBody::Link& link = cloth->m_links[l];
        if (link.m_bbending) continue;  // strain is measured on the structural and shear links
        const double len = (link.m_n[1]->m_x - link.m_n[0]->m_x).length();
        r.max_strain = std::max(r.max_strain, (len - link.m_rl) / link.m_rl);
      }
  }
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu = process_cpu_seconds() - c0;
  r.finite = std::isfinite(cloth->m_nodes[side * side / 2].m_x.y());
  world.removeSoftBody(cloth);
  delete cloth;
  return r;
}

void print_row(const char* name, double seconds, const PeerResult& r, const PeerResult& ref) {
  const double particle_steps = double(side) * side * r.steps / r.wall;
  std::printf("%-20s %10.3g %7ld %9.3f %9.3f %12.4f %11.4f %14.4g %11.4f %15.3f %14.3f %s\n", name, r.dt, r.steps,
              r.wall, r.cpu, seconds / r.wall, seconds / r.cpu, particle_steps, r.max_strain, r.wall / ref.wall,
              r.cpu / ref.cpu, r.finite ? "" : "(diverged)");
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 1.0;
  const double cs_dt = argc > 2 ? std::atof(argv[2]) : 5e-5;
  const double stiffness = argc > 3 ? std::atof(argv[3]) : 3000;
  const double bt_dt = argc > 4 ? std::atof(argv[4]) : 1.0 / 240;
  const int iterations = argc > 5 ? std::atoi(argv[5]) : 4;
  const char* integrator_name = argc > 6 ? argv[6] : "symplectic";
  const int threads = argc > 7 ? std::atoi(argv[7]) : 2;
  const double cg_tolerance = argc > 8 ? std::atof(argv[8]) : 1e-6;
  Integrator integrator = Integrator::symplectic;
  if (!enum_from_name(integrator_names, integrator_name, integrator) || integrator == Integrator::euler) {
    std::fprintf(stderr, "clothsim_peer_bullet: integrator '%s'; expected symplectic, implicit or rk4\n",
                 integrator_name);
    return 2;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  std::printf("128 x 128 sheet, 1 m, 1 kg, two corners pinned, %.3g s simulated, clothsim %s at %d threads, "
              "Bullet %d iterations\n", seconds, integrator_name, threads, iterations);
  const PeerResult cs = run_clothsim(seconds, cs_dt, stiffness, integrator, cg_tolerance);
  const PeerResult bt = run_bullet(seconds, bt_dt, iterations);
  std::printf("%-20s %10s %7s %9s %9s %12s %11s %14s %11s %15s %14s\n", "peer", "dt_s", "steps", "wall_s", "cpu_s",
              "sim_s/wall_s", "sim_s/cpu_s", "particle_st/s", "max_strain", "cs_vs_peer_wall", "cs_vs_peer_cpu");
  const std::string cs_name = std::string("clothsim ") + integrator_name;
  print_row(cs_name.c_str(), seconds, cs, cs);
  print_row("bullet", seconds, bt, cs);
  return 0;
}
