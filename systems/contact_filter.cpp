#include "systems/contact_filter.h"

#include "systems/collision/response.h"
#include "systems/parallel.h"
#include "systems/reduce.h"

namespace clothsim {

void clear_contact_holds(const Model& m, CollisionScratch& s) {
  if (s.acc_hold.empty()) return;
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    s.acc_hold_count[i] = 0;
    for (int k = 0; k < 7; ++k) s.acc_hold[7 * std::size_t(i) + k] = 0;
  });
}

void gather_contact_holds(const Model& m, const CollisionScratch& s, State& out) {
  if (s.acc_hold.empty()) return;
  if (out.contact.size() != std::size_t(m.particle_count)) out.contact.assign(m.particle_count, ContactHold{});
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    const std::int32_t count = s.acc_hold_count[i];
    const std::int64_t* sum = &s.acc_hold[7 * std::size_t(i)];
    auto mean = [&](int k) { return Real(sum[k]) / (fixed_scale * count); };
    ContactHold c;
    if (count > 0) {
      const Vec3 n(mean(0), mean(1), mean(2));
      const Real len = n.norm();
      if (len >= contact_filter_agreement) c = {n / len, Vec3(mean(3), mean(4), mean(5)), mean(6)};
    }
    out.contact[i] = c;
  });
}

bool prepare_contact_filter(const Model& m, const State& in, Workspace& ws) {
  CollisionScratch& s = ws.collision;
  if (s.filter_normal.empty()) return false;
  const bool known = in.contact.size() == std::size_t(m.particle_count);
  const Index held = deterministic_sum(m.particle_count, particle_grain, Index(0), [&](Index i) {
    s.held_impulse[i] = 0;
    s.filter_normal[i] = known && m.particle_inv_mass[i] > 0 ? in.contact[i].normal : Vec3(Vec3::Zero());
    return Index(s.filter_normal[i].squaredNorm() > 0);
  });
  return held > 0;
}

void filter_held(const Workspace& ws, std::span<Vec3> w) {
  const std::vector<Vec3>& n = ws.collision.filter_normal;
  parallel_over(Index(w.size()), particle_grain, [&](Index i) {
    if (n[i].squaredNorm() > 0) w[i] -= n[i] * n[i].dot(w[i]);
  });
}

void start_filtered_solve(Workspace& ws) {
  CollisionScratch& s = ws.collision;
  parallel_over(Index(ws.cg_r.size()), particle_grain, [&](Index i) {
    Vec3& n = s.filter_normal[i];
    if (!(n.squaredNorm() > 0)) return;
    s.held_rhs[i] = n.dot(ws.cg_r[i]);
    if (s.held_rhs[i] > 0) {
      n = Vec3::Zero();  // the particle's forces already pull it off the body: not held
      return;
    }
    ws.cg_r[i] -= s.held_rhs[i] * n;
  });
}

void finish_filtered_solve(const Model& m, std::span<const Vec3> x, Real h, ImplicitLayout layout, Workspace& ws) {
  CollisionScratch& s = ws.collision;
  apply_system(m, x, h, layout, ws, ws.cg_x, ws.cg_q);
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    const Vec3& n = s.filter_normal[i];
    if (n.squaredNorm() > 0) s.held_impulse[i] += n.dot(ws.cg_q[i]) - s.held_rhs[i];
  });
}

void apply_held_friction(const Model& m, const State& in, State& out, const Workspace& ws, Real h) {
  const CollisionScratch& s = ws.collision;
  parallel_over(m.particle_count, particle_grain, [&](Index i) {
    const Vec3& n = s.filter_normal[i];
    const Real lambda = s.held_impulse[i];
    if (!(n.squaredNorm() > 0) || !(lambda > 0)) return;
    const ContactHold& c = in.contact[i];
    const Vec3 rel = out.v[i] - c.velocity;
    const Vec3 vt = rel - n * n.dot(rel);
    const Real vt_len = vt.norm(), cone = c.friction * lambda * m.particle_inv_mass[i];
    if (!(vt_len > 0)) return;
    const Vec3 change = -std::min(Real(1), cone / vt_len) * vt;
    out.v[i] += change;
    out.x[i] += h * change;
  });
}

}  // namespace clothsim
