#pragma once
// Compressed sparse rows of the model's incidences, built by a counting sort straight from the arrays they
// index (no owner/entry pair lists: at a million particles those cost 96 bytes a particle while building).
#include <vector>

#include "core/math.h"
#include "core/scene_desc.h"

namespace clothsim {

struct Model;

// The incident springs of every particle: entry = spring index, ~index (negative) when the particle is
// spring_b; entries of one particle in spring order, so a gather over them sums in the same order at any thread
// count.
void build_particle_springs(const Model& model, std::vector<Index>& offset, std::vector<Index>& index);
// Fills model.particle_spring_offset / particle_spring_index.
void build_particle_springs(Model& model);
// Whether the model's kernels, stepped by `integrator`, read the spring CSR: the gather layout and the implicit
// integrator. The blocked layout alone does not (nor the strain limit, which sweeps by colour), and the model then
// goes without it.
bool needs_particle_springs(const Model& model, Integrator integrator);
// Builds the spring CSR where the model needs it and lacks it: for a model stepped by an integrator, or given a
// layout, other than the ones it was built for (the studies run one model with every integrator).
void ensure_particle_springs(Model& model, Integrator integrator);

// The incident hinges of every particle, entry = 4 * hinge + slot (0: o1, 1: o2, 2: e0, 3: e1), in hinge order:
// model.particle_hinge_offset / particle_hinge_index (core/hinges.h).
void build_particle_hinges(Model& model);

// The incident triangles of every particle, in triangle order: model.particle_tri_offset / particle_tri_index.
void build_particle_tris(Model& model);

}  // namespace clothsim
