#include "systems/collision/impact_zones.h"

#include <algorithm>
#include <cmath>

#include "systems/collision/contacts.h"
#include "systems/collision/reach_grid.h"
#include "systems/parallel.h"

namespace clothsim {

void reset_zones(ZoneScratch& z) {
  parallel_over(Index(z.parent.size()), particle_grain, [&](Index x) {
    z.parent[x] = x;
    z.flag[x] = 0;
  });
  z.zone_count = 0;
}

// After a pass has linked its pairs: every zone node points straight at its root (ascending, a node's parent is
// smaller than it and already points at the root, so one look-up each), and the zones holding a node of this
// pass's pairs are numbered by root, ascending, with their members ascending in a CSR. Sequential and linear in
// the node count: it runs only in steps with crossings left, where the detection passes cost far more.
void gather_zones(ZoneScratch& z) {
  const Index n = Index(z.parent.size());
  for (Index k = 0; k < z.zone_count; ++k) z.slot[z.member[z.offset[k]]] = -1;  // a zone's first member is its root
  for (Index x = 0; x < n; ++x)
    if (z.flag[x] & zone_member) z.parent[x] = z.parent[z.parent[x]];
  for (Index x = 0; x < n; ++x)
    if (z.flag[x] & zone_touched) z.slot[z.parent[x]] = -2;
  z.zone_count = 0;
  for (Index x = 0; x < n; ++x)
    if (z.slot[x] == -2) z.slot[x] = z.zone_count++;
  std::fill(z.offset.begin(), z.offset.begin() + z.zone_count + 1, 0);
  for (Index x = 0; x < n; ++x)
    if ((z.flag[x] & zone_member) && z.slot[z.parent[x]] >= 0) ++z.offset[z.slot[z.parent[x]] + 1];
  for (Index k = 0; k < z.zone_count; ++k) z.offset[k + 1] += z.offset[k];
  for (Index x = 0; x < n; ++x)
    if ((z.flag[x] & zone_member) && z.slot[z.parent[x]] >= 0) z.member[z.offset[z.slot[z.parent[x]]]++] = x;
  for (Index k = z.zone_count; k > 0; --k) z.offset[k] = z.offset[k - 1];
  z.offset[0] = 0;
  for (Index x = 0; x < n; ++x) z.flag[x] &= std::uint8_t(~zone_touched);
}

namespace {

// One member of a zone: where it starts and ends the step, its mass, and whether it is immovable (a collider
// vertex, or a pinned particle: infinite mass).
struct ZoneNode {
  Vec3 x0, x1;
  Real mass = 0;
  bool fixed = false;
};

ZoneNode zone_node(const Model& m, const State& in, const State& out, const CollisionScratch& s, Index node) {
  ZoneNode z;
  if (node < m.particle_count) {
    z.x0 = in.x[node];
    z.x1 = out.x[node];
    z.fixed = m.particle_inv_mass[node] == 0;
    z.mass = z.fixed ? 0 : 1 / m.particle_inv_mass[node];
  } else {
    z.x0 = s.collider_x0[node - m.particle_count];
    z.x1 = s.collider_x1[node - m.particle_count];
    z.fixed = true;
  }
  return z;
}

// A free zone (cloth particles only) moves as a rigid body over the step (Bridson et al. 2002 §6.3): the rigid
// motion fitted to its members' displacements over the step (their average velocities (x1 - x0) / h, which
// include the position-only pushes of the responses) carries every member from its start position,
// x1 = c + h v + R(h omega) (x0 - c): distances within the zone are kept exactly. The end velocities are a rigid
// field with the linear and angular momentum of the members' velocities before the fit (about the centre of
// mass, the angular one with the inertia of the new positions), so the zone keeps both momenta to rounding;
// the fit of the displacements is not used for them, since a push of a thickness in one step is no velocity
// (it would be metres per second).
void move_free_zone(const Model& m, const State& in, State& out, const Index* member, int count, Real h) {
  const RigidFit motion = fit_rigid_motion(count, [&](int j, Real& w, Vec3& x, Vec3& u) {
    const Index i = member[j];
    w = 1 / m.particle_inv_mass[i];
    x = in.x[i];
    u = (out.x[i] - in.x[i]) / h;
  });
  const RigidFit momenta = fit_rigid_motion(count, [&](int j, Real& w, Vec3& x, Vec3& u) {
    const Index i = member[j];
    w = 1 / m.particle_inv_mass[i];
    x = out.x[i];
    u = out.v[i];
  });
  const Mat3 r = rotation_of(h * motion.omega);
  const Vec3 moved = motion.center + h * motion.velocity;
  Vec3 c = Vec3::Zero();
  for (int j = 0; j < count; ++j) {
    const Index i = member[j];
    out.x[i] = moved + r * (in.x[i] - motion.center);
    c += out.x[i] / m.particle_inv_mass[i];
  }
  c /= momenta.weight;
  const Vec3 omega = solve_inertia(inertia_about(count, c, [&](int j, Real& w, Vec3& x, Vec3& u) {
                                     w = 1 / m.particle_inv_mass[member[j]];
                                     x = out.x[member[j]];
                                     u = Vec3::Zero();
                                   }),
                                   momenta.momentum);
  for (int j = 0; j < count; ++j) out.v[member[j]] = momenta.velocity + omega.cross(out.x[member[j]] - c);
}

// A zone holding immovable nodes (collider vertices, pinned particles) has infinite mass there: as their mass
// grows, the mass-weighted fit tends to the fit over them alone, so the zone takes the collider's motion. A body
// is not rigid over a zone that spans a shoulder and a neck, though, and cloth touching it must go where the body
// goes at that place, not with a compromise over the whole zone (one fit per zone left several times the
// unresolved steps on the real bodies: docs/performance.md, "Rigid impact zones"). So each cloth particle of the
// zone follows the rigid motion fitted to the zone's immovable nodes weighted by 1 / (d^2 + e^2)^2, d their start
// distance from it (e: 1% of its thickness): the body's motion next to it, rotation included, from the body
// vertices its zone's pairs touched. Its velocity is that motion's at its end position; no momentum is kept (the
// collider absorbs it). The particles of such a zone no longer move as one rigid body; pairs among them that a
// differing motion brings together are found by the next pass like any other.
void move_attached_zone(const Model& m, const State& in, State& out, const CollisionScratch& s, const Index* member,
                        int count, Real h) {
  for (int j = 0; j < count; ++j) {
    const Index i = member[j];
    if (i >= m.particle_count || m.particle_inv_mass[i] == 0) continue;
    const Real e2 = std::pow(0.01 * m.particle_thickness[i], 2);
    const RigidFit motion = fit_rigid_motion(count, [&](int k, Real& w, Vec3& x, Vec3& u) {
      const ZoneNode n = zone_node(m, in, out, s, member[k]);
      w = 0;
      if (n.fixed) w = 1 / std::pow((n.x0 - in.x[i]).squaredNorm() + e2, 2);
      x = n.x0;
      u = (n.x1 - n.x0) / h;
    });
    const Vec3 moved = motion.center + h * motion.velocity;
    out.x[i] = moved + rotation_of(h * motion.omega) * (in.x[i] - motion.center);
    out.v[i] = motion.velocity + motion.omega.cross(out.x[i] - moved);
  }
}

}  // namespace

void rigidify_zones(const Model& m, const State& in, State& out, const CollisionScratch& s, Real h) {
  const ZoneScratch& z = s.zones;
  parallel_over(z.zone_count, 1, [&](Index k) {
    const Index* member = &z.member[z.offset[k]];
    const int count = int(z.offset[k + 1] - z.offset[k]);
    bool attached = false;
    for (int j = 0; j < count && !attached; ++j) attached = zone_node(m, in, out, s, member[j]).fixed;
    if (attached) move_attached_zone(m, in, out, s, member, count, h);
    else move_free_zone(m, in, out, member, count, h);
  });
}

void count_zones(ZoneScratch& z, ZoneFigures& figures) {
  const Index n = Index(z.parent.size());
  for (Index k = 0; k < z.zone_count; ++k) z.slot[z.member[z.offset[k]]] = -1;
  z.zone_count = 0;
  for (Index x = 0; x < n; ++x)
    if (z.flag[x] & zone_member) z.parent[x] = z.parent[z.parent[x]];
  // slot counts a root's members here (it is -1 everywhere else), then goes back to -1.
  for (Index x = 0; x < n; ++x)
    if (z.flag[x] & zone_member) {
      Index& size = z.slot[z.parent[x]];
      size = size < 0 ? 1 : size + 1;
    }
  for (Index x = 0; x < n; ++x)
    if (z.slot[x] > 0) {
      ++figures.zones;
      figures.zone_nodes += z.slot[x];
      figures.largest = std::max(figures.largest, std::int64_t(z.slot[x]));
      z.slot[x] = -1;
    }
}

// A kept pair has a zone member among its particles, so growing each member's swept path by a particle's reach
// (systems/collision/reach_grid.h) covers every element that can have a kept pair.
void gather_reach_boxes(const Model& m, const State& in, const State& out, const CollisionScratch& s,
                        ZoneScratch& z) {
  const Real grow_by = reach_of_a_particle(m, s);
  z.reach.clear();
  for (Index i = 0; i < m.particle_count; ++i)
    if (z.flag[i] & zone_member) z.reach.push_back({z.parent[i], i});
  std::sort(z.reach.begin(), z.reach.end());
  z.reach_box.clear();
  for (std::size_t k = 0; k < z.reach.size(); ++k) {
    const Index i = z.reach[k][1];
    const Aabb path = swept_box(in.x[i], out.x[i]);
    if (k == 0 || z.reach[k][0] != z.reach[k - 1][0]) {
      z.reach_box.push_back(path);
    } else {
      grow(z.reach_box.back(), path.lo);
      grow(z.reach_box.back(), path.hi);
    }
  }
  for (Aabb& b : z.reach_box) {
    b.lo.array() -= grow_by;
    b.hi.array() += grow_by;
  }
}

bool near_a_zone(const ZoneScratch& z, const Aabb& q) {
  for (const Aabb& b : z.reach_box)
    if (boxes_overlap(q, b)) return true;
  return false;
}

// Each pass finds the pairs the continuous pass would still respond to (find_crossings), merges their nodes (cloth
// particles; collider vertices as node particle_count + v) into zones, and moves the zones that grew, until a pass
// finds none. It stops early, the step counted as unresolved, when a pass merges nothing (every pair found lies
// within one zone) or after model.collision.zone_iterations passes. The pairs are those of the continuous pass, met
// within the thickness, not only actual crossings: a squeezed sheet left micrometres from a body would otherwise be
// held there by its zone, crossing and all (docs/performance.md, "Rigid impact zones"). So an unresolved step may end
// with pairs that only graze within the thickness.
ZoneFigures resolve_impact_zones(const Model& m, const State& in, State& out, CollisionScratch& s, BroadMode mode,
                                 Real h) {
  const CollisionModel& c = m.collision;
  ZoneScratch& z = s.zones;
  ZoneFigures figures;
  reset_zones(z);
  ++figures.steps;
  bool clean = false;
  for (int pass = 0; pass < c.zone_iterations; ++pass) {
    build_cloth_broad_phase(m, in, out, s);
    std::atomic<std::int64_t> links{0};
    // After the first pass, a pair none of whose cloth particles is in a zone has not moved since that pass
    // found it apart (collider vertices move the same in every pass): only pairs touching a zone are tested. The
    // flags read are the earlier passes': this pass merges its pairs only after detecting all of them.
    // The first pass likewise tests only pairs with a particle the last continuous pass moved (s.crossed).
    auto moved = [&](const Index* p, int count) {
      if (pass == 0) return crossed(s, p, count);
      for (int k = 0; k < count; ++k)
        if (z.flag[p[k]] & zone_member) return true;
      return false;
    };
    // Those pairs come only from elements near a zone (near a particle the continuous pass moved, in the first
    // pass): the walk skips the rest before their broad-phase query.
    if (pass == 0) build_reach_grid(in, out, s.crossed, reach_of_a_particle(m, s), s.crossed_reach);
    else gather_reach_boxes(m, in, out, s, z);
    auto near = [&](const Aabb& q) { return pass == 0 ? reaches(s.crossed_reach, q) : near_a_zone(z, q); };
    const Index pairs = find_crossings(m, in, out, s, mode, moved, near);
    parallel_over(pairs, contact_grain, [&](Index k) {
      Index nodes[4];
      contact_nodes(m, s.contacts[std::size_t(k)], nodes);
      if (const int merged = add_zone_pair(z, nodes, 4)) links.fetch_add(merged, std::memory_order_relaxed);
    });
    ++figures.passes;
    if (pairs == 0) {
      clean = true;
      break;
    }
    if (links.load() == 0) break;
    gather_zones(z);
    rigidify_zones(m, in, out, s, h);
  }
  if (!clean) ++figures.unresolved;
  count_zones(z, figures);
  return figures;
}

}  // namespace clothsim
