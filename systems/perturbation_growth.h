#pragma once
// Instability seen at its onset: the growth of a small perturbation under the step map, where the divergence
// check of run_diverges sees it only once it has grown to the energy bound or torn a spring (docs/stability.md,
// "The automatic step against the largest stable step").
#include <cstdint>
#include <span>
#include <vector>

#include "core/model.h"

namespace clothsim {

// Runs `steps` steps of h from start and, side by side, from a twin moved by up to 1e-9 m a coordinate (a fixed
// pseudo-random offset of every free particle), in `windows` equal windows. Returns for each window the natural
// log of the factor by which the twin's deviation grew in it, the deviation being
// sqrt(sum m |v_twin - v|^2 + sum_springs ke (l_twin - l)^2) (l a spring's length: a rigid motion, which a stable
// run need not damp, does not count). After each window the twin is scaled back to its start deviation (Benettin
// et al. 1980), so the growth is the linearised step map's along the run. +inf for a window in which either
// state stops being finite. Empty when nothing moves. Deterministic sums: the same at any thread count.
std::vector<Real> perturbation_growth(const Model& model, const SimOptions& options, const State& start, Real h,
                                      std::int64_t steps, int windows);

// Per window, how much faster the perturbation grows at h than at h / 2 (over the same windows of time): the log
// growth at h less that at h / 2. Growth of the physics (a swing, a contact, buckling) is the same at both steps
// and cancels; an instability of the step at h shows (at h / 2 the mode is stable, or grows at less than half the
// rate: explicit Euler's mode grows at gamma (r - 1) / 2 per second at r times its limit). +inf where the run at h
// stops being finite.
std::vector<Real> growth_over_half_step(const Model& model, const SimOptions& options, const State& start, Real h,
                                        std::int64_t steps, int windows);

// True when the second half of the windows shows exponential growth: no window in it shrinks the deviation and
// together they grow it by at least `factor`. Past a mode's limit the step map grows that mode by the same
// factor every window; at a stable step the deviation decays, or grows in bursts (contact, buckling) that
// later windows undo.
bool grows_exponentially(std::span<const Real> window_log_growth, Real factor = 10);

}  // namespace clothsim
