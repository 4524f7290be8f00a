#pragma once
// A seeded family of small scene files for the stability estimate and the automatic step (docs/stability.md):
// grid sizes, densities, stiffnesses, spring and air damping, pins, each explicit integrator, with and without a
// collider. `clothsim study autostep` and tests/scenario/stability_family_test.cpp run it.
#include <string>

#include "core/model.h"

namespace clothsim::io {

struct FamilyScene {
  std::string xml;
  // Every spring has the same ke and kd and there is no wind: C = (kd/ke) K + c M, so the estimate's stiffest
  // mode is an exact mode of the damped system and 2x its limit must diverge.
  bool proportional = false;
};

// Scene `seed` of the family (deterministic); timestep is written as given ("auto" or seconds).
FamilyScene family_scene(int seed, const std::string& timestep = "0.001");

// Moves every free particle by up to amount/2 m along each axis (deterministic): a generic start state excites
// every mode, as round-off does in a long run.
void perturb_start(const Model& model, State& state, Real amount);

}  // namespace clothsim::io
