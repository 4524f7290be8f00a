#include "core/scene_desc.h"

#include <cmath>

#include "core/error.h"
#include "core/limits.h"
#include "core/step_count.h"

namespace clothsim {

std::int64_t steps_per_frame_count(double fps, double timestep) {
  // Compared in double before any conversion: a count past the limit (or an infinite one, when fps * timestep
  // underflows) is reported as limit + 1, never cast, as casting an out-of-range double is undefined.
  const double n = std::ceil(1.0 / (fps * timestep) * (1.0 - 1e-9));
  if (!(n <= double(limits::max_steps_per_frame))) return limits::max_steps_per_frame + 1;
  return n < 1 ? 1 : static_cast<std::int64_t>(n);
}

int steps_per_frame(const SimulationDesc& sim) {
  const std::int64_t n = steps_per_frame_count(sim.fps, sim.timestep);
  if (n > limits::max_steps_per_frame)
    throw Error("", "timestep " + std::to_string(sim.timestep) + " s at fps " + std::to_string(sim.fps) +
                        " needs more than " + std::to_string(limits::max_steps_per_frame) +
                        " steps a frame; expected at most that many (docs/errors.md)");
  return int(n);
}

}  // namespace clothsim
