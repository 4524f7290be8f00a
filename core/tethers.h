#pragma once
// Long-range attachments (Kim, Chentanez & Müller-Fischer 2012, "Long Range Attachments - A Method to Simulate
// Inextensible Clothing in Computer Games", SCA 2012): each free particle of a strain-limited cloth that has pins
// is tied to its nearest pin, and the strain limit (systems/strain_limit.h) first pulls every particle farther
// from that pin than (1 + maxStrain) times its rest distance back onto that sphere, one independent projection a
// particle. A sheet stretched as a whole (a drop held by two corners) is then mostly fixed before the spring
// sweeps start, which only propagate a correction a few springs per sweep.
#include <span>
#include <vector>

#include "core/model.h"

namespace clothsim {

// Fills model.tether_particle / tether_pin / tether_length for the cloths whose springs have a finite maxStrain
// and which have a pinned particle with springs. The nearest pin is found by Dijkstra over the springs' rest
// lengths (from all pins at once; ties go to the pin settled first, a fixed order). The rest distance to it is
// the straight line between the rest positions where straight_rest[c] is set for cloth c (a flat, convex rest
// shape: a grid), else the shortest path over the springs: never shorter than the cloth's geodesic, so the tether
// allows every configuration whose springs are all within the limit (each spring of the path is at most
// (1 + maxStrain) rest long).
void build_tethers(Model& model, std::span<const Vec3> rest_positions, std::span<const char> straight_rest);

}  // namespace clothsim
