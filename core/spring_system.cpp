#include "core/spring_system.h"

#include "core/csr.h"
#include "core/error.h"

namespace clothsim {

BuiltScene build_spring_system(const SpringSystemDesc& d) {
  BuiltScene out;
  Model& m = out.model;
  out.options.integrator = d.integrator;
  m.gravity = d.gravity;
  m.particle_count = Index(d.positions.size());
  if (d.masses.size() != d.positions.size())
    throw Error("spring system", "expected one mass per particle, got " + std::to_string(d.masses.size()) +
                                     " masses for " + std::to_string(d.positions.size()) + " particles");
  for (Index i = 0; i < m.particle_count; ++i) {
    m.particle_inv_mass.push_back(d.masses[i] > 0 ? 1.0 / d.masses[i] : 0.0);
    if (!(d.masses[i] > 0)) m.pinned.push_back(i);
  }
  m.particle_thickness = ParamField(0.0);

  m.spring_count = Index(d.spring_a.size());
  for (Index s = 0; s < m.spring_count; ++s) {
    const Index a = d.spring_a[s], b = d.spring_b[s];
    if (a < 0 || b < 0 || a >= m.particle_count || b >= m.particle_count || a == b)
      throw Error("spring system", "spring " + std::to_string(s) + " joins particles " + std::to_string(a) +
                                       " and " + std::to_string(b) + "; expected two distinct particles below " +
                                       std::to_string(m.particle_count));
    const Real rest = (d.positions[b] - d.positions[a]).norm();
    if (!(rest > 0)) throw Error("spring system", "spring " + std::to_string(s) + " has zero rest length");
    m.spring_a.push_back(a);
    m.spring_b.push_back(b);
    m.spring_rest.push_back(rest);
  }
  m.spring_ke = ParamField(d.stiffness);
  m.spring_kd = ParamField(d.damping);
  m.particle_stiffness = ParamField(d.stiffness);
  m.spring_kind_total[int(SpringKind::edge)] = m.spring_count;
  build_particle_springs(m);
  m.particle_tri_offset.assign(std::size_t(m.particle_count) + 1, 0);

  out.state = make_state(m, d.positions);
  return out;
}

}  // namespace clothsim
