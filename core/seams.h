#pragma once
// The seam table of the collision model: which particles a stitched garment's seams make neighbours, not
// contacts (docs/garments.md, "Seams in contact").
#include "core/model.h"

namespace clothsim {

// A seam's reach, in thicknesses: particles this close at rest through a seam are neighbours (build_seams).
inline constexpr Real seam_reach_thicknesses = 2;

// Fills c.seam_offset / c.seam_index from the model's stitches (nothing without stitches).
void build_seams(const Model& m, CollisionModel& c);

}  // namespace clothsim
