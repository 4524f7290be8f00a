#include "core/hinges.h"

#include "core/model.h"
#include "core/topology.h"

namespace clothsim {

void append_hinges(Model& m, const Topology& topo, Index base, std::span<const Vec3> rest, Real bend_modulus) {
  const std::size_t total = std::size_t(m.hinge_count) + std::size_t(topo.bend_count());
  for (auto* v : {&m.hinge_e0, &m.hinge_e1, &m.hinge_o1, &m.hinge_o2}) v->reserve(total);
  m.hinge_rest_angle.reserve(total);
  m.hinge_k.reserve(total);
  // k = (D / 6) 3 |e|^2 / (A1 + A2) = D |e|^2 / (|N1| + |N2|) with |Ni| = 2 Ai.
  for (Index h = 0; h < topo.bend_count(); ++h) {
    const Index o1 = base + topo.bend_a[h], o2 = base + topo.bend_b[h];
    const Index e0 = base + topo.edge_a[topo.bend_edge[h]], e1 = base + topo.edge_b[topo.bend_edge[h]];
    const HingeFrame f = hinge_frame(rest[o1], rest[o2], rest[e0], rest[e1]);
    if (!hinge_live(f)) continue;
    m.hinge_e0.push_back(e0);
    m.hinge_e1.push_back(e1);
    m.hinge_o1.push_back(o1);
    m.hinge_o2.push_back(o2);
    m.hinge_rest_angle.push_back(hinge_angle(f));
    m.hinge_k.push_back(bend_modulus * f.e_len * f.e_len / (std::sqrt(f.n1_sq) + std::sqrt(f.n2_sq)));
    ++m.hinge_count;
  }
}

}  // namespace clothsim
