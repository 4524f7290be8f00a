#include "core/build_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/attachments.h"
#include "core/csr.h"
#include "core/build_collision.h"
#include "core/error.h"
#include "core/grid.h"
#include "core/hinges.h"
#include "core/spring_chunks.h"
#include "core/spring_colours.h"
#include "core/stitches.h"
#include "core/tethers.h"
#include "core/topology.h"
#include "core/transform.h"

namespace clothsim {
namespace {

// Springs of one cloth: the grid rule for grids; one edge spring per unique edge and one bend spring across
// each interior manifold edge for meshes. With dihedral bending the hinges take the place of the bend and flex
// springs, which are not created (so the blocked layout and the implicit blocks see only stretch and shear).
SpringList cloth_springs(const ClothDesc& cloth, const Topology& topo) {
  const bool hinges = cloth.bending == Bending::dihedral;
  SpringList s;
  if (cloth.grid_nx > 0) {
    s = make_grid_springs(cloth.grid_nx, cloth.grid_ny);
    if (hinges) {
      SpringList kept;
      for (Index k = 0; k < s.size(); ++k)
        if (s.kind[k] != SpringKind::flex) kept.add(s.a[k], s.b[k], s.kind[k]);
      s = std::move(kept);
    }
    return s;
  }
  s.a.reserve(topo.edge_count() + (hinges ? 0 : topo.bend_count()));
  for (Index e = 0; e < topo.edge_count(); ++e) s.add(topo.edge_a[e], topo.edge_b[e], SpringKind::edge);
  if (!hinges)
    for (Index e = 0; e < topo.bend_count(); ++e) s.add(topo.bend_a[e], topo.bend_b[e], SpringKind::bend);
  return s;
}

Real kind_scale(const ClothDesc& cloth, SpringKind k) {
  switch (k) {
    case SpringKind::shear: return cloth.shear_scale;
    case SpringKind::bend:
    case SpringKind::flex: return cloth.bend_scale;
    default: return 1;
  }
}

// A cloth's per-vertex parameter: the sampled array when its map was given, else its one uniform value.
ParamField vertex_field(const SceneDesc& scene, const ClothDesc& cloth, const MeshData& mesh,
                        const std::vector<Real>& sampled, Real uniform, const char* what) {
  if (sampled.empty()) return ParamField(uniform);
  if (Index(sampled.size()) != mesh.vertex_count())
    throw Error(scene.path, cloth.line, "cloth '" + cloth.name + "': " + what + " has " +
                                            std::to_string(sampled.size()) + " values; expected one per vertex (" +
                                            std::to_string(mesh.vertex_count()) + ")");
  return ParamField::from_values(sampled);
}

// A cloth's stitches: its OBJ's records, its <stitch> pairs (range-checked here) and its weld pairs.
void add_cloth_stitches(const SceneDesc& scene, const ClothDesc& cd, const MeshData& mesh, Index base,
                        const std::vector<Vec3>& positions, const ParamField& stiffness, const ParamField& damping,
                        Model& m) {
  StitchList s{mesh.stitch_a, mesh.stitch_b, mesh.stitch_c, mesh.stitch_w};
  for (std::size_t k = 0; k + 1 < cd.stitch_pairs.size(); k += 2) {
    const Index i = cd.stitch_pairs[k], j = cd.stitch_pairs[k + 1];
    if (i >= mesh.vertex_count() || j >= mesh.vertex_count() || i == j)
      throw Error(scene.path, cd.line,
                  "cloth '" + cd.name + "': stitch " + std::to_string(i) + " " + std::to_string(j) +
                      " is out of range or sews a vertex to itself; expected two distinct vertices of 0.." +
                      std::to_string(mesh.vertex_count() - 1));
    s.add(i, j, j, 0);
  }
  const std::span<const Vec3> x(positions.data() + base, std::size_t(mesh.vertex_count()));
  add_weld_stitches(mesh, x, cd.weld, s);
  append_stitches(m, s, base, positions, stiffness, damping, cd.sew_speed);
}

}  // namespace

MeshData make_cloth_grid(const ClothDesc& cloth) {
  return make_grid_mesh(cloth.grid_nx, cloth.grid_ny, cloth.grid_w, cloth.grid_h);
}

BuiltScene build_model(const SceneDesc& scene, const std::vector<MeshData>& meshes) {
  return build_model(scene, std::vector<MeshData>(meshes));
}

BuiltScene build_model(const SceneDesc& scene, std::vector<MeshData>&& meshes) {
  BuiltScene out;
  Model& m = out.model;
  const SimulationDesc& sim = scene.simulation;
  out.options = make_sim_options(sim);
  m.gravity = sim.gravity + scene.forces.external_acceleration;
  m.wind_velocity = scene.forces.wind_velocity;
  m.wind_strength = scene.forces.wind_strength;
  m.air_damping = scene.forces.air_damping;
  m.random = scene.forces.random;

  // Arrays are reserved to their final size: growing by doubling would briefly hold twice a large array.
  std::size_t total_vertices = 0, total_tris = 0;
  for (const MeshData& mesh : meshes) {
    total_vertices += mesh.positions.size();
    total_tris += mesh.tri_index.size();
  }
  std::vector<Vec3> positions;
  positions.reserve(total_vertices);
  // Rest positions (<cloth rest>): rest lengths, masses and tethers come from them; the cloth's own positions for
  // cloths without a rest mesh. Held apart only when some cloth has one.
  const bool own_rest = std::any_of(meshes.begin(), meshes.end(), [](const MeshData& d) { return !d.rest_positions.empty(); });
  std::vector<Vec3> rest_x;
  if (own_rest) rest_x.reserve(total_vertices);
  const std::vector<Vec3>& rest = own_rest ? rest_x : positions;
  m.tri_index.reserve(total_tris);
  std::vector<Real> mass, area;
  std::vector<char> pinned_flag;
  mass.reserve(total_vertices);
  area.reserve(total_vertices);
  pinned_flag.reserve(total_vertices);
  ParamFieldBuilder ke, kd, thickness, stretch, max_strain;
  std::vector<char> straight_rest;  // per cloth: a grid, whose flat rectangle makes rest distances straight lines

  for (std::size_t c = 0; c < scene.cloths.size(); ++c) {
    const ClothDesc& cd = scene.cloths[c];
    MeshData& mesh = meshes[c];
    const Index base = m.particle_count;
    ClothInfo info;
    info.name = cd.name;
    info.texture = cd.texture;
    info.friction = cd.friction;
    info.restitution = cd.restitution;
    info.thickness = cd.thickness;
    info.self_collision = cd.self_collision;
    info.cloth_collision = scene.simulation.cloth_collision && cd.cloth_collision;
    info.particle_begin = base;
    info.particle_end = base + mesh.vertex_count();
    info.tri_begin = m.tri_count;
    info.tri_end = m.tri_count + mesh.triangle_count();
    info.uvs = std::move(mesh.uvs);
    info.tri_uv = std::move(mesh.tri_uv);
    // UV indices equal to the vertex indices (grids, and OBJs whose vt follow their v) are not stored twice.
    if (!info.tri_uv.empty() && info.tri_uv == mesh.tri_index) {
      info.uv_per_vertex = true;
      std::vector<Index>().swap(info.tri_uv);
    }

    for (const Vec3& p : mesh.positions) positions.push_back(apply_transform(cd.transform, p));
    if (own_rest)
      for (const Vec3& p : mesh.rest_positions.empty() ? mesh.positions : mesh.rest_positions)
        rest_x.push_back(apply_transform(cd.transform, p));
    mass.resize(positions.size(), 0.0);
    area.resize(positions.size(), 0.0);
    pinned_flag.resize(positions.size(), 0);
    const VertexParams& vp = mesh.params;
    const ParamField density = vertex_field(scene, cd, mesh, vp.density, cd.density, "density map");
    const ParamField stiffness = vertex_field(scene, cd, mesh, vp.stiffness, cd.stiffness, "stiffness map");
    const ParamField damping = vertex_field(scene, cd, mesh, vp.damping, cd.damping, "damping map");
    const ParamField vertex_thickness = vertex_field(scene, cd, mesh, vp.thickness, cd.thickness, "thickness map");
    for (Index i = 0; i < mesh.vertex_count(); ++i) {
      thickness.push(vertex_thickness[i]);
      stretch.push(stiffness[i]);
    }
    // With a thickness map the cloth's one figure is its largest thickness (a safe bound for collision queries).
    info.thickness = vertex_thickness[0];
    for (Index i = 0; i < mesh.vertex_count(); ++i) info.thickness = std::max(info.thickness, vertex_thickness[i]);

    // Mass from areal density lumped to the corners by rest area (a third each), so refining keeps the total; a
    // rest mesh (a garment's flat pattern) holds the cloth's material, however a drape stretches it.
    for (Index t = 0; t < mesh.triangle_count(); ++t) {
      Index g[3];
      for (int k = 0; k < 3; ++k) g[k] = base + mesh.tri_index[3 * t + k];
      const Real a = 0.5 * (rest[g[1]] - rest[g[0]]).cross(rest[g[2]] - rest[g[0]]).norm();
      for (int k = 0; k < 3; ++k) {
        area[g[k]] += a / 3;
        mass[g[k]] += density[mesh.tri_index[3 * t + k]] * a / 3;
        m.tri_index.push_back(g[k]);
      }
    }
    m.tri_count += mesh.triangle_count();
    // A mass map or <mass> gives kg per vertex as written (the original tool's rule); vertices no triangle
    // touches keep no mass, as with density.
    if (cd.mass_per_vertex) {
      const ParamField vertex_mass = vertex_field(scene, cd, mesh, vp.mass, cd.mass, "mass map");
      for (Index i = 0; i < mesh.vertex_count(); ++i)
        mass[base + i] = area[base + i] > 0 ? vertex_mass[i] : 0.0;
    }
    if (!vp.pinned.empty()) {
      if (Index(vp.pinned.size()) != mesh.vertex_count())
        throw Error(scene.path, cd.line, "cloth '" + cd.name + "': pins map has the wrong size; expected one value per vertex");
      for (Index i = 0; i < mesh.vertex_count(); ++i) pinned_flag[base + i] |= vp.pinned[i];
    }

    for (Index p : cd.pins) {
      if (p < 0 || p >= mesh.vertex_count())
        throw Error(scene.path, cd.line,
                    "cloth '" + cd.name + "': pinned vertex " + std::to_string(p) + " is out of range (the mesh has " +
                        std::to_string(mesh.vertex_count()) + " vertices, numbered from 0)");
      pinned_flag[base + p] = 1;
    }
    mark_attachments(scene, cd, mesh, base, pinned_flag, m);

    straight_rest.push_back(cd.grid_nx > 0 && mesh.rest_positions.empty());
    // Grids are one piece; their topology is built only for hinges (the grid rule gives their springs).
    Topology topo;
    if (cd.grid_nx == 0 || cd.bending == Bending::dihedral) topo = build_topology(mesh);
    info.pieces = cd.grid_nx > 0 ? 1 : topo.pieces;
    SpringList springs = cloth_springs(cd, topo);
    if (cd.bending == Bending::dihedral) append_hinges(m, topo, base, rest, cd.bend_modulus);
    topo = Topology();
    info.spring_begin = m.spring_count;
    while (info.bend_springs < springs.size() && springs.kind[springs.size() - 1 - info.bend_springs] == SpringKind::bend)
      ++info.bend_springs;
    const std::size_t spring_total = std::size_t(m.spring_count) + springs.size();
    m.spring_a.reserve(spring_total);
    m.spring_b.reserve(spring_total);
    m.spring_rest.reserve(spring_total);
    for (Index s = 0; s < springs.size(); ++s) {
      const Index a = base + springs.a[s], b = base + springs.b[s];
      const Real rest_length = (rest[b] - rest[a]).norm();
      if (!(rest_length > 0))
        throw Error(scene.path, cd.line,
                    "cloth '" + cd.name + "': vertices " + std::to_string(springs.a[s]) + " and " +
                        std::to_string(springs.b[s]) + " coincide" + (cd.rest.empty() ? "" : " in the rest mesh " + cd.rest) +
                        " (zero-length spring); expected distinct positions");
      m.spring_a.push_back(a);
      m.spring_b.push_back(b);
      m.spring_rest.push_back(rest_length);
      // A spring takes the mean of its ends' values; for a uniform value 0.5 * (k + k) is k exactly.
      ke.push(0.5 * (stiffness[springs.a[s]] + stiffness[springs.b[s]]) * kind_scale(cd, springs.kind[s]));
      kd.push(0.5 * (damping[springs.a[s]] + damping[springs.b[s]]));
      max_strain.push(cd.max_strain > 0 ? cd.max_strain : std::numeric_limits<Real>::infinity());
      m.strain_limited = m.strain_limited || cd.max_strain > 0;
      ++m.spring_kind_total[int(springs.kind[s])];
    }
    m.spring_count += springs.size();
    springs = SpringList();
    add_cloth_stitches(scene, cd, mesh, base, positions, stiffness, damping, m);
    mesh = MeshData();  // this cloth's mesh is built: free it before the next one
    info.spring_end = m.spring_count;
    m.particle_count = info.particle_end;
    m.cloths.push_back(std::move(info));
  }

  m.spring_ke = ke.finish();
  m.spring_kd = kd.finish();
  m.particle_thickness = thickness.finish();
  m.particle_stiffness = stretch.finish();
  if (m.strain_limited) m.spring_max_strain = max_strain.finish();

  // Vertices no triangle touches carry no mass: they stay where they are, like pins.
  m.particle_inv_mass.resize(m.particle_count);
  for (Index i = 0; i < m.particle_count; ++i) {
    const bool fixed = pinned_flag[i] || !(mass[i] > 0);
    m.particle_inv_mass[i] = fixed ? 0.0 : 1.0 / mass[i];
    if (fixed) m.pinned.push_back(i);
  }
  if (m.needs_normals()) m.particle_area = std::move(area);

  build_particle_tris(m);
  if (m.stitch_count > 0) build_particle_stitches(m);
  if (m.hinge_count > 0) build_particle_hinges(m);
  // Each spring computed once and no per-spring buffer, where the spring order allows it (docs/performance.md).
  if (build_spring_chunks(m)) m.spring_layout = SpringLayout::blocked;
  // The spring CSR only when a kernel of this model reads it (the blocked layout alone does not).
  if (needs_particle_springs(m, out.options.integrator)) build_particle_springs(m);
  // The strain limit's colour schedule and long-range attachments (systems/strain_limit.h).
  if (m.strain_limited) {
    build_spring_colours(m);
    build_tethers(m, rest, straight_rest);
  }

  out.state = make_state(m, std::move(positions));
  return out;
}

State make_state(const Model& model, std::vector<Vec3> positions) {
  State s;
  s.x = std::move(positions);
  s.v.assign(model.particle_count, Vec3::Zero());
  return s;
}

Workspace make_workspace(const Model& model, const SimOptions& options) {
  Workspace ws;
  ws.f.assign(model.particle_count, Vec3::Zero());
  if (options.integrator == Integrator::rk4) {
    ws.stage_x.assign(model.particle_count, Vec3::Zero());
    ws.stage_v.assign(model.particle_count, Vec3::Zero());
  }
  ws.normal.assign(model.particle_count, Vec3::Zero());
  ws.stitch_rest.assign(model.stitch_count, 0);
  ws.stitch_pull.assign(model.stitch_count, 0);
  ws.hinge_force.assign(4 * std::size_t(model.hinge_count), Vec3::Zero());
  if (options.integrator == Integrator::implicit) {
    for (auto* buf : {&ws.cg_x, &ws.cg_r, &ws.cg_p, &ws.cg_q}) buf->assign(model.particle_count, Vec3::Zero());
    if (options.solver.newton_iterations > 1) ws.dv.assign(model.particle_count, Vec3::Zero());
    ws.cg_precond.assign(model.particle_count, Sym3{});
    // Float blocks are a backward error of 6e-8 (core/math.h): kept in double where the solve is asked for more.
    if (options.solver.preconditioner == Preconditioner::cholesky || options.solver.cg_tolerance < kFloatBlockTolerance)
      ws.spring_block_f64.assign(model.spring_count, Sym3{});
    else
      ws.spring_block_f32.assign(model.spring_count, Sym3f{});
    ws.stitch_kx.assign(model.stitch_count, Sym3{});
    ws.stitch_block.assign(model.stitch_count, Sym3{});
    ws.hinge_jac.assign(4 * std::size_t(model.hinge_count), Vec3::Zero());
    if (options.solver.preconditioner == Preconditioner::multigrid) ws.multigrid = build_multigrid_levels(model);
    if (options.solver.preconditioner == Preconditioner::cholesky) ws.cholesky = build_cholesky_factor(model);
  }
  make_collision_workspace(model, ws.collision);
  if (options.integrator == Integrator::implicit && options.solver.contact_filter && model.collision.enabled &&
      !model.collision.colliders.empty()) {
    CollisionScratch& s = ws.collision;
    s.acc_hold.assign(7 * std::size_t(model.particle_count), 0);
    s.acc_hold_count.assign(model.particle_count, 0);
    s.filter_normal.assign(model.particle_count, Vec3::Zero());
    s.held_impulse.assign(model.particle_count, 0);
    s.held_rhs.assign(model.particle_count, 0);
    if (model.strain_limited) {
      s.contact_offset.assign(model.particle_count, 0);
      s.collided_x.assign(model.particle_count, Vec3::Zero());
    }
  }
  return ws;
}

}  // namespace clothsim
