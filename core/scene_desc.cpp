#include "core/scene_desc.h"

#include <cmath>

namespace clothsim {

int steps_per_frame(const SimulationDesc& sim) {
  const double ratio = 1.0 / (sim.fps * sim.timestep);
  const int n = static_cast<int>(std::ceil(ratio * (1.0 - 1e-9)));
  return n < 1 ? 1 : n;
}

}  // namespace clothsim
