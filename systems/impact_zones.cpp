#include "systems/impact_zones.h"

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

}  // namespace

// Each refitted zone moves as a rigid body over the step (Bridson et al. 2002 §6.3): the rigid motion fitted to
// its members' displacements over the step (their average velocities (x1 - x0) / h, which include the
// position-only pushes of the responses) carries every member from its start position, x1 = c + h v + R(h omega)
// (x0 - c): distances within the zone are kept exactly. The end velocities are a rigid field with the linear
// and angular momentum of the members' velocities before the fit (about the centre of mass, the angular one
// with the inertia of the new positions), so a free zone keeps both momenta to rounding; the fit of the
// displacements is not used for them, since a push of a thickness in one step is no velocity (it would be
// metres per second).
//
// A zone holding immovable nodes (collider vertices, pins) has infinite mass there: as their mass grows, the
// mass-weighted fit tends to the fit over them alone, so the zone takes the collider's motion -- the rigid
// motion that best fits its collider vertices' displacement -- and its cloth moves with the body that pushes
// it, at that motion's velocity; no momentum is kept (the collider absorbs it). Where the collider bends
// within the zone (two limbs closing on the cloth), the fit is the least-squares compromise and crossings can
// remain: counted as unresolved.
void rigidify_zones(const Model& m, const State& in, State& out, const CollisionScratch& s, Real h) {
  const ZoneScratch& z = s.zones;
  parallel_over(z.zone_count, 1, [&](Index k) {
    const Index* member = &z.member[z.offset[k]];
    const int count = int(z.offset[k + 1] - z.offset[k]);
    bool any_fixed = false;
    for (int j = 0; j < count && !any_fixed; ++j) any_fixed = zone_node(m, in, out, s, member[j]).fixed;
    // The fit of the displacements: masses, or the immovable nodes alone.
    const RigidFit motion = fit_rigid_motion(count, [&](int j, Real& w, Vec3& x, Vec3& u) {
      const ZoneNode n = zone_node(m, in, out, s, member[j]);
      w = any_fixed ? Real(n.fixed) : n.mass;
      x = n.x0;
      u = (n.x1 - n.x0) / h;
    });
    // The momenta of the velocities before the fit, at the positions they belong to (free zones only).
    RigidFit momenta;
    if (!any_fixed)
      momenta = fit_rigid_motion(count, [&](int j, Real& w, Vec3& x, Vec3& u) {
        const Index i = member[j];
        w = 1 / m.particle_inv_mass[i];
        x = out.x[i];
        u = out.v[i];
      });
    const Mat3 r = rotation_of(h * motion.omega);
    const Vec3 moved = motion.center + h * motion.velocity;
    for (int j = 0; j < count; ++j) {
      const Index i = member[j];
      if (i >= m.particle_count || m.particle_inv_mass[i] == 0) continue;
      out.x[i] = moved + r * (in.x[i] - motion.center);
    }
    if (any_fixed) {
      for (int j = 0; j < count; ++j) {
        const Index i = member[j];
        if (i < m.particle_count && m.particle_inv_mass[i] != 0)
          out.v[i] = motion.velocity + motion.omega.cross(out.x[i] - moved);
      }
      return;
    }
    // Free zone: the centre of mass and inertia after the move, then omega = I^+ L.
    auto at_end = [&](int j, Real& w, Vec3& x, Vec3& u) {
      w = 1 / m.particle_inv_mass[member[j]];
      x = out.x[member[j]];
      u = Vec3::Zero();
    };
    Vec3 c = Vec3::Zero();
    for (int j = 0; j < count; ++j) c += out.x[member[j]] / m.particle_inv_mass[member[j]];
    c /= momenta.weight;
    const Vec3 omega = solve_inertia(inertia_about(count, c, at_end), momenta.momentum);
    for (int j = 0; j < count; ++j) out.v[member[j]] = momenta.velocity + omega.cross(out.x[member[j]] - c);
  });
}

void count_zones(ZoneScratch& z) {
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
      ++z.zones;
      z.zone_nodes += z.slot[x];
      z.largest = std::max(z.largest, z.slot[x]);
      z.slot[x] = -1;
    }
}

}  // namespace clothsim
