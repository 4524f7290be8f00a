#pragma once
// Candidate lists reused across one step's broad-phase walks. The collide stage walks the BVH up to a dozen times
// a step (proximity and continuous passes, impact zones, the cloth holds) while the cloth moves by a fraction of
// its thickness between walks. So once the step's broad phase is built, each cloth element's query box, grown by
// twice a margin, is walked once and every slot it meets is kept. A later walk filters an element's list by the
// boxes the broad phase then holds, when the element's particles lie within the margin (per axis) of where the
// lists were made: every cloth box made from corners within the margin too is then in the list if it meets the
// query, and the few cloth boxes made from corners farther away (runaways) are tested apart. An element farther
// away walks the trees. The pairs found are exactly a fresh walk's (the contact buffer's order is free:
// systems/collision/contacts.h), so the results are the same bytes as without the lists.
#include "core/model.h"

namespace clothsim {

// The cloth elements a walk queries for: vertices (proximity and continuous vertex walks), triangles (against
// collider vertices), edges.
enum class WalkKind { vertex, triangle, edge };

// The margin, in cloth thicknesses. A smaller one makes smaller boxes and shorter lists, and more cloth triangles
// run away within a step; a quarter took the collide phase of the Rumba's frames 0-12 from 9.4 s to 8.3 s against
// one thickness, with 0.1 and 0.05 no better (docs/performance.md, "Candidate lists reused within a step").
inline constexpr Real candidate_margin_thicknesses = 0.25;
// Elements per block of a kind's lists.
inline constexpr Index candidate_block = 256;
// Runaway slots beyond which the lists are not worth filtering: the walks go back to the trees.
inline constexpr std::size_t runaway_limit = 512;

// Makes the lists for the broad phase just built for (in, out), when the scene's broad phase is the BVH.
void make_candidate_lists(const Model& model, const State& in, const State& out, CollisionScratch& s);
// Turns the lists off (a new broad phase, for other positions, is being built).
inline void drop_candidate_lists(CollisionScratch& s) { s.candidates.on = false; }
// Records that the cloth's boxes are being rebuilt from `out`: the slots with a corner beyond the margin.
void note_cloth_boxes(const Model& model, const State& in, const State& out, CollisionScratch& s);
// The lists of `kind` when a walk from `in` may use them, else null.
const CandidateLists* usable_candidates(const State& in, const CollisionScratch& s, WalkKind kind);

// Whether particles p[0, n) of `out` all lie within the margin of where the lists were made.
inline bool near_lists(const CandidateCache& k, const State& out, const Index* p, int n) {
  for (int j = 0; j < n; ++j)
    if (!((out.x[p[j]] - k.x_ref[p[j]]).cwiseAbs().maxCoeff() <= k.margin * (1 - 1e-9))) return false;
  return true;
}

}  // namespace clothsim
