#include "core/sim_options.h"

namespace clothsim {

SimOptions make_sim_options(const SimulationDesc& sim) {
  SimOptions o;
  o.integrator = sim.integrator;
  o.steps_per_frame = steps_per_frame(sim);
  o.fps = sim.fps;
  o.dt = 1.0 / (sim.fps * o.steps_per_frame);
  o.auto_step = sim.timestep_auto;
  o.step_safety = sim.step_safety;
  o.min_dt = sim.min_timestep;
  o.start_frame = sim.start_frame;
  o.end_frame = sim.end_frame;
  o.solver = {sim.cg_tolerance, sim.cg_max_iterations, sim.newton_iterations, sim.preconditioner,
              sim.contact_filter};
  return o;
}

}  // namespace clothsim
