#include "systems/strain_limit.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <vector>

#include "systems/displace.h"
#include "systems/parallel.h"

namespace clothsim {
namespace {

// Springs per task within one colour: a projection is a few tens of nanoseconds, so 1024 keep the task overhead
// small while a 128^2 sheet's colour (about 7,500 springs) still splits over several threads.
constexpr Index colour_grain = 1024;
constexpr Real no_excess = -std::numeric_limits<Real>::infinity();

// Largest of body(k) over the schedule entries [begin, end), in parallel. max is exact and order-free, so the
// result does not depend on how the range is split. A range of one grain runs here, without a task: late sweeps
// project a few marked springs a colour, where the task machinery cost more than the projections.
template <class Body>
Real max_over(Index begin, Index end, Body&& body) {
  if (end - begin <= colour_grain) {
    Real worst = no_excess;
    for (Index k = begin; k < end; ++k) worst = std::max(worst, body(k));
    return worst;
  }
  return tbb::parallel_reduce(
      tbb::blocked_range<Index>(begin, end, colour_grain), no_excess,
      [&](const tbb::blocked_range<Index>& r, Real worst) {
        for (Index k = r.begin(); k != r.end(); ++k) worst = std::max(worst, body(k));
        return worst;
      },
      [](Real p, Real q) { return std::max(p, q); });
}

// How far spring s of length len is past its limit, in strain: (len - rest)/rest - maxStrain.
inline Real strain_excess(const Model& m, Index s, Real len) {
  const Real rest = m.spring_rest[s];
  return (len - rest) / rest - m.spring_max_strain[s];
}

// Kim et al. 2012 §3: a particle outside its tether's sphere goes straight back onto it; the pin does not move.
void apply_tethers(const Model& m, State& out, Real h) {
  parallel_over(Index(m.tether_particle.size()), particle_grain, [&](Index t) {
    const Index i = m.tether_particle[t];
    const Vec3 d = out.x[i] - out.x[m.tether_pin[t]];
    const Real len = d.norm(), limit = m.tether_length[t];
    if (len > limit) displace(out, i, ((limit - len) / len) * d, h);
  });
}

// Which springs a sweep must project again. One found within its limit (excess <= 0) whose ends have not moved
// since gives the same excess again and moves nothing, so skipping it changes no byte; a move of a particle marks
// every spring at it. Late sweeps work on a few pinched regions while the rest of the cloth is settled, so a sweep
// costs what its marked springs cost. The marks are set from several threads but only ever to 1, and read after
// the colour that set them has ended, so which springs run does not depend on the threads.
struct SweepMarks {
  std::vector<std::atomic<std::uint8_t>> dirty;  // per schedule entry
  std::vector<Index> colour_list;                // the marked entries of the colour being swept
  explicit SweepMarks(const Model& m) : dirty(m.spring_colour_spring.size()) {
    for (auto& d : dirty) d.store(1, std::memory_order_relaxed);
  }
  void mark(const Model& m, Index i) {
    for (Index e = m.particle_colour_offset[i]; e < m.particle_colour_offset[i + 1]; ++e)
      dirty[std::size_t(m.particle_colour_entry[e])].store(1, std::memory_order_relaxed);
  }
};

// One Gauss-Seidel sweep: colours in order, each colour's springs in parallel (they share no particle). A spring
// longer than L = (1 + maxStrain) rest moves its ends towards each other by omega (|d| - L), split by inverse mass
// (Provot 1995 §5; omega = 1 is his projection). Returns the largest strain excess met, before each projection,
// over the springs it projected (the skipped ones are within their limit).
Real sweep(const Model& m, State& out, Real h, Real omega, SweepMarks& marks) {
  Real met = no_excess;
  const Index colours = Index(m.spring_colour_offset.size()) - 1;
  std::vector<Index>& list = marks.colour_list;
  for (Index c = 0; c < colours; ++c) {
    list.clear();
    for (Index k = m.spring_colour_offset[c]; k < m.spring_colour_offset[c + 1]; ++k)
      if (marks.dirty[std::size_t(k)].load(std::memory_order_relaxed)) list.push_back(k);
    met = std::max(met, max_over(0, Index(list.size()), [&](Index j) {
      const Index k = list[std::size_t(j)], s = m.spring_colour_spring[k], a = m.spring_a[s], b = m.spring_b[s];
      marks.dirty[std::size_t(k)].store(0, std::memory_order_relaxed);
      const Vec3 d = out.x[b] - out.x[a];
      const Real len = d.norm(), excess = strain_excess(m, s, len);
      if (excess > 0) {
        const Real wa = m.particle_inv_mass[a], wb = m.particle_inv_mass[b];
        const Real target = (1 + m.spring_max_strain[s]) * m.spring_rest[s];
        const Vec3 dx = (omega * (len - target) / ((wa + wb) * len)) * d;
        displace(out, a, wa * dx, h);
        displace(out, b, -wb * dx, h);
        marks.mark(m, a);
        marks.mark(m, b);
      }
      return excess;
    }));
  }
  return met;
}

}  // namespace

Real strain_limit_excess(const Model& m, std::span<const Vec3> x) {
  return max_over(0, Index(m.spring_colour_spring.size()), [&](Index k) {
    const Index s = m.spring_colour_spring[k];
    return strain_excess(m, s, (x[m.spring_b[s]] - x[m.spring_a[s]]).norm());
  });
}

bool strain_limit_met(const Model& m, std::span<const Vec3> x) {
  return strain_limit_excess(m, x) <= 0.5 * strain_limit_tolerance;
}

namespace {

// The sweeps of apply_strain_limit, each followed by after_sweep(out, moved) when one is given, which reports each
// particle it moves to `moved`: the springs at those are marked for the next sweep.
int limit_strain(const Model& m, State& out, Real h, const ContactHoldPass& after_sweep = {}) {
  // Stop a little inside the guarantee so the last sweep's round-off cannot cross it (strain_limit_met).
  const Real stop = 0.5 * strain_limit_tolerance;
  if (strain_limit_met(m, out.x)) return 0;
  apply_tethers(m, out, h);
  int it = 0;
  // The tethers alone may leave nothing to do (a chain stretched straight from its pin).
  bool done = !m.tether_particle.empty() && strain_limit_met(m, out.x);
  SweepMarks marks(m);
  const MovedParticle moved = [&](Index i) { marks.mark(m, i); };
  while (!done && it < strain_limit_max_iterations) {
    // The first sweep projects exactly: a spring stretched alone ends at its limit, not past it.
    const Real met = sweep(m, out, h, it == 0 ? 1 : strain_limit_relaxation, marks);
    if (after_sweep) after_sweep(out, moved);
    ++it;
    // The read-only check of the end state decides; it runs after the first sweep (one sweep is often enough)
    // and after any sweep that met no spring past the stop, so most steps check once or twice, not every sweep.
    done = (it == 1 || met <= stop) && strain_limit_met(m, out.x);
  }
  return it;
}

}  // namespace

int apply_strain_limit(const Model& m, State& out, Real h) {
  return limit_strain(m, out, h);
}

void set_contact_planes(const Model& m, const State& out, std::span<Real> offset) {
  parallel_over(m.particle_count, particle_grain, [&](Index i) { offset[i] = out.contact[i].normal.dot(out.x[i]); });
}

int apply_strain_limit_on_contacts(const Model& m, State& out, Real h, std::span<const Real> offset,
                                   const ContactHoldPass& hold) {
  const auto onto_planes = [&](State& s, const MovedParticle& moved) {
    parallel_over(m.particle_count, particle_grain, [&](Index i) {
      const Vec3& n = s.contact[i].normal;
      const Real behind = offset[i] - n.dot(s.x[i]);
      if (!(behind > 0)) return;
      displace(s, i, behind * n, h);
      moved(i);  // marks, set from any thread, only ever to 1
    });
    if (hold) hold(s, moved);
  };
  // A stitch pass since set_contact_planes may have moved a contact behind its plane; every spring starts marked.
  onto_planes(out, [](Index) {});
  return limit_strain(m, out, h, onto_planes);
}

}  // namespace clothsim
