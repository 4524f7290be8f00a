#pragma once
// Where a scattered set of cloth particles can be met: the cells of a uniform grid that the particles' swept paths,
// grown by a reach, overlap. The continuous passes after the first and the impact zones' first pass test only
// pairs with such a particle (systems/collision/contacts.h, crossed); their walks skip every element whose box
// meets no marked cell before its broad-phase query. One list of boxes would do for a few compact zones, but the
// particles a continuous pass moved lie all over a garment.
#include "core/model.h"

namespace clothsim {

// How far an element that can have a pair with particle i may lie from i's swept path: a pair's element meets (within
// the thickness, for an edge pair) the box of a cloth triangle with i as a corner, or is i's own. So the largest
// cloth prim box (thickness included, s.prim_box of the cloth's broad phase) plus the thickness again.
Real reach_of_a_particle(const Model& model, const CollisionScratch& s);

// Marks the cells that each particle with flag[i] == 1 reaches: its swept path from in.x to out.x grown by
// `reach` on every side. Cells of side `reach`. Over a quarter of the particles flagged, or no reach, marks
// everywhere.
void build_reach_grid(const State& in, const State& out, const std::vector<std::uint8_t>& flag, Real reach,
                      ReachGrid& g);

// Whether box q overlaps a marked cell: true whenever q overlaps one of the grown paths.
bool reaches(const ReachGrid& g, const Aabb& q);

}  // namespace clothsim
