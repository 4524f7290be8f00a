#pragma once
// Building a model's stitches (Model::stitch_*): the cloth OBJ's records, the scene's <stitch> pairs and the
// pairs <cloth weld> finds, with their stiffness, start gap and sewing time (systems/stitch_forces.h).
#include <span>
#include <vector>

#include "core/mesh_data.h"
#include "core/param_field.h"

namespace clothsim {

struct Model;

// One cloth's stitches, indices local to its mesh; weld pairs are added by add_weld_stitches.
struct StitchList {
  std::vector<Index> a, b, c;
  std::vector<Real> w;
  void add(Index ia, Index ib, Index ic, Real wc) {
    a.push_back(ia);
    b.push_back(ib);
    c.push_back(ic);
    w.push_back(wc);
  }
};

// Pairs (i, j) of boundary vertices of different connected pieces of the mesh with |x_i - x_j| <= distance,
// each vertex sewn to its nearest such vertex (a pair found from both sides counts once), as stitches i -> j
// with w = 0. Sorted by (i, j), so the result does not depend on the search order.
void add_weld_stitches(const MeshData& mesh, std::span<const Vec3> x, Real distance, StitchList& out);

// Appends a cloth's stitches to the model, indices shifted by base (the cloth's first particle); x are the
// model's positions so far. Stiffness and damping are those of the sewn vertex a; the sewing target shrinks
// from the start gap to 0 at sew_speed (m/s).
void append_stitches(Model& m, const StitchList& s, Index base, std::span<const Vec3> x, const ParamField& stiffness,
                     const ParamField& damping, Real sew_speed);

// The incident stitches of every particle (model.particle_stitch_offset / particle_stitch_index), entries in
// stitch order, so a gather over them sums in the same order at any thread count.
void build_particle_stitches(Model& m);

}  // namespace clothsim
