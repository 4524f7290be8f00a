#include "core/memory_bytes.h"

namespace clothsim {
namespace {

template <class T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

template <class... V>
std::size_t sum_bytes(const V&... v) {
  return (bytes(v) + ...);
}

}  // namespace

std::size_t model_bytes(const Model& m) {
  std::size_t total = sum_bytes(m.particle_inv_mass, m.particle_area, m.pinned, m.spring_a, m.spring_b,
                                m.spring_rest, m.particle_spring_offset, m.particle_spring_index,
                                m.spring_chunk_offset, m.spring_pass_offset, m.spring_pass_chunk,
                                m.spring_chunk_open_offset, m.spring_chunk_open_range, m.spring_chunk_close_offset,
                                m.spring_chunk_close_range, m.spring_block_close, m.tri_index,
                                m.particle_tri_offset, m.particle_tri_index, m.spring_colour_offset,
                                m.spring_colour_spring, m.particle_colour_offset, m.particle_colour_entry,
                                m.tether_particle, m.tether_pin, m.tether_length,
                                m.attach_particle, m.attach_collider, m.attach_tri, m.attach_weight, m.attach_offset,
                                m.hinge_e0, m.hinge_e1, m.hinge_o1, m.hinge_o2, m.hinge_rest_angle, m.hinge_k,
                                m.particle_hinge_offset, m.particle_hinge_index);
  total += m.particle_thickness.bytes() + m.particle_stiffness.bytes() + m.spring_ke.bytes() + m.spring_kd.bytes() +
           m.spring_max_strain.bytes();
  for (const ClothInfo& c : m.cloths) total += sum_bytes(c.uvs, c.tri_uv);
  return total;
}

std::size_t state_bytes(const State& s) { return sum_bytes(s.x, s.v, s.contact); }

std::size_t multigrid_bytes(const Multigrid& mg) {
  std::size_t total = std::size_t(mg.dense.size() + mg.dense_factor.size() + mg.dense_rhs.size()) * sizeof(Real);
  for (const MultigridLevel& l : mg.levels)
    total += sum_bytes(l.parent, l.member_offset, l.member_index, l.row_offset, l.row_col, l.row_edge,
                       l.source_offset, l.source_index, l.ground_offset, l.ground_index, l.edge_block, l.diag,
                       l.diag_inv, l.b, l.x, l.t);
  return total;
}

std::size_t workspace_bytes(const Workspace& ws) {
  return sum_bytes(ws.f, ws.stage_x, ws.stage_v, ws.normal, ws.stitch_rest, ws.stitch_pull, ws.dv, ws.cg_x, ws.cg_r,
                   ws.cg_p, ws.cg_q, ws.cg_precond, ws.spring_block_f64, ws.spring_block_f32, ws.stitch_kx,
                   ws.stitch_block, ws.hinge_force, ws.hinge_jac) +
         multigrid_bytes(ws.multigrid) + (ws.cholesky ? cholesky_bytes(*ws.cholesky) : 0);
}

}  // namespace clothsim
