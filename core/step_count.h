#pragma once
// The number of steps a frame takes, as a 64-bit count checked against limits::max_steps_per_frame before
// anything narrows it: 1/(fps * timestep) can exceed any int (timestep 1e-11 s, fps 1e-9).
#include <cstdint>

namespace clothsim {

// ceil(1/(fps * timestep)) with steps_per_frame's tolerance (core/scene_desc.h), at least 1; any count past
// limits::max_steps_per_frame (an infinite one included) is returned as that limit + 1.
std::int64_t steps_per_frame_count(double fps, double timestep);

}  // namespace clothsim
