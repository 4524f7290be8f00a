#pragma once
// The strain limit's Gauss-Seidel schedule (systems/strain_limit.h), built once with the model: the springs it
// projects, grouped into colours so that no two springs of one colour share a particle. A sweep runs the colours
// in order and the springs of one colour in parallel: each projection reads and writes only its own two
// particles, which no other spring of the colour touches, so a sweep gives the same bytes at any thread count.
#include "core/model.h"

namespace clothsim {

// Whether the strain limit projects spring s: it has a finite maxStrain and at least one end that can move.
bool spring_is_limited(const Model& model, Index s);

// Fills model.spring_colour_offset / spring_colour_spring with the limited springs: greedy, in spring order, each
// spring taking the lowest colour free at both its ends (a grid's Provot springs take 13 colours, at most
// 2 x the largest particle degree - 1 in general). Within a colour springs keep their index order. Also fills
// particle_colour_offset / particle_colour_entry: each particle's schedule entries, in entry order.
void build_spring_colours(Model& model);

}  // namespace clothsim
