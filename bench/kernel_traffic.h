#pragma once
// Compulsory traffic and work of each kernel per item, the figures docs/performance.md's roofline uses.
// Bytes count each array element a kernel must stream once (neighbour positions re-read from cache are free);
// they assume the uniform stiffness/damping of the bench sheet (ParamField stride 0, no per-spring array).
#include <cstdint>

#include <span>
#include <vector>

#include "core/model.h"
#include "systems/spring_forces.h"

namespace clothsim::bench {

// The spring-force layouts the benchmarks compare: the model's two, and two-phase, which no model selects
// (systems/spring_forces.h).
enum class BenchLayout { gather, two_phase, blocked };

// f = the spring forces in `layout`; two_phase writes its per-spring forces into `spring_force` (spring_count).
inline void eval_springs_as(BenchLayout layout, const Model& m, std::span<const Vec3> x, std::span<const Vec3> v,
                            std::span<Vec3> f, std::span<Vec3> spring_force) {
  switch (layout) {
    case BenchLayout::gather: eval_springs_gather(m, x, v, f); break;
    case BenchLayout::two_phase: eval_springs_two_phase(m, x, v, f, spring_force); break;
    case BenchLayout::blocked: eval_springs_blocked(m, x, v, f); break;
  }
}

constexpr double vec3_bytes = 3 * sizeof(Real);
constexpr double index_bytes = sizeof(Index);

// gather: per particle x, v read, f written, one offset; per spring two CSR entries, each reading a, b, rest.
inline double bytes_springs_gather(const Model& m) {
  return m.particle_count * (3 * vec3_bytes + index_bytes) +
         m.spring_count * 2 * (index_bytes + 2 * index_bytes + sizeof(Real));
}
// two_phase: phase 1 reads x, v, a, b, rest and writes the spring force; phase 2 reads two CSR entries and the
// force once (the second end hits cache), and writes f.
inline double bytes_springs_two_phase(const Model& m) {
  return m.particle_count * (3 * vec3_bytes + index_bytes) +
         m.spring_count * (2 * index_bytes + sizeof(Real) + vec3_bytes + 2 * index_bytes + vec3_bytes);
}
// blocked: per particle x, v read once (neighbours within a chunk hit cache), f zeroed and then read-modified-
// written; per spring a, b, rest.
inline double bytes_springs_blocked(const Model& m) {
  return m.particle_count * 5 * vec3_bytes + m.spring_count * (2 * index_bytes + sizeof(Real));
}
// The model's own layout among the benchmarks'.
inline BenchLayout model_layout(const Model& m) {
  return m.spring_layout == SpringLayout::blocked ? BenchLayout::blocked : BenchLayout::gather;
}
inline double bytes_springs(const Model& m, BenchLayout layout) {
  switch (layout) {
    case BenchLayout::gather: return bytes_springs_gather(m);
    case BenchLayout::two_phase: return bytes_springs_two_phase(m);
    case BenchLayout::blocked: return bytes_springs_blocked(m);
  }
  return 0;
}
// external forces: read f, v, inv_mass, write f.  symplectic integrate: read x, v, a, write x, v.
inline double bytes_external(const Model& m) { return m.particle_count * (3 * vec3_bytes + sizeof(Real)); }
inline double bytes_integrate(const Model& m) { return m.particle_count * 5 * vec3_bytes; }
// Fused blocked stage (systems/forces.h): x, v read once, f allocated and written back once, inv_mass read;
// the springs' a, b, rest. The integrator's update adds only the arrays it alone touches.
inline bool fused(const Model& m) { return m.spring_layout == SpringLayout::blocked && m.fuse_particle_pass; }
inline double bytes_forces_fused(const Model& m) {
  return m.particle_count * (4 * vec3_bytes + sizeof(Real)) + m.spring_count * (2 * index_bytes + sizeof(Real));
}
// One symplectic step with the model's layout; fused, the update only writes x', v'.
inline double bytes_step_symplectic(const Model& m) {
  if (fused(m)) return bytes_forces_fused(m) + m.particle_count * 2 * vec3_bytes;
  const double springs = bytes_springs(m, model_layout(m));
  return springs + bytes_external(m) + bytes_integrate(m);
}
// RK4: four force stages and four per-particle update passes (each reads/writes about 8 Vec3 per particle);
// fused, an update adds x0, v0 read, the two sums read and written, the stage state written back (8 Vec3).
inline double bytes_step_rk4(const Model& m) {
  if (fused(m)) return 4 * (bytes_forces_fused(m) + m.particle_count * 8 * vec3_bytes);
  const double springs = bytes_springs(m, model_layout(m));
  return 4 * (springs + bytes_external(m)) + 4 * m.particle_count * 8 * vec3_bytes;
}
// normals: per particle reads x of the incident triangles (cache), CSR offset, writes the normal; per triangle
// three CSR entries and three corner indices.
inline double bytes_normals(const Model& m) {
  return m.particle_count * (2 * vec3_bytes + index_bytes) + m.tri_count * 3 * (index_bytes + 3 * index_bytes);
}

}  // namespace clothsim::bench
