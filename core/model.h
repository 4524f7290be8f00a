#pragma once
// The immutable physics of a simulation (Model; how it is stepped is SimOptions, core/sim_options.h), the only thing
// a step changes (State), and the scratch sized once when the model is built (Workspace). All are
// structure-of-arrays: one contiguous buffer per field, named <entity>_<attr>, with shape and units in a comment.
#include <array>
#include <string>
#include <vector>

#include "core/collision_model.h"
#include "core/math.h"
#include "core/cholesky_factor.h"
#include "core/multigrid_levels.h"
#include "core/param_field.h"
#include "core/scene_desc.h"
#include "core/sim_options.h"

namespace clothsim {

enum class SpringKind : std::uint8_t { edge, bend, structural, shear, flex };
inline constexpr int spring_kind_count = 5;
inline constexpr std::array<const char*, spring_kind_count> spring_kind_names{
    "edge", "bend", "structural", "shear", "flex"};

// How spring forces are accumulated without floating-point races (docs/performance.md, "Spring-force layouts").
enum class SpringLayout {
  gather,   // per particle over a CSR of incident springs: each spring computed twice
  blocked,  // each spring once, scattered into f by chunks; chunks of one pass touch disjoint particles
};

// What output, reporting and the collision response need of one cloth; kept out of the arrays the kernels stream.
// Where its frames go (saveDir, saveName) is the scene's (ClothDesc), not the Model's.
struct ClothInfo {
  std::string name;
  std::string texture;       // colour texture, resolved against the scene folder ("" for none)
  Index particle_begin = 0, particle_end = 0;
  Index tri_begin = 0, tri_end = 0;
  Index spring_begin = 0, spring_end = 0;
  // A mesh cloth's bend springs come last: [spring_end - bend_springs, spring_end). A grid has none of that kind
  // (its flex springs, interleaved, can never stretch more than the two structural springs they span).
  Index bend_springs = 0;
  std::vector<Vec2> uvs;     // texture coordinates (uv_count)
  std::vector<Index> tri_uv; // uv index per corner, local to this cloth (3 * triangles), empty without UVs
  bool uv_per_vertex = false; // UV index = local vertex index (grids; OBJs whose vt follow v): tri_uv stays empty
  Index pieces = 0;          // connected components
  Real friction = 0, restitution = 0, thickness = 0;
  bool self_collision = false;   // collides with itself
  bool cloth_collision = false;  // collides with the other cloths that have it (scene and cloth settings both on)
};

struct Model {
  // --- particles
  Index particle_count = 0;
  std::vector<Real> particle_inv_mass;  // 1/kg, 0 for pinned (particle_count)
  std::vector<Real> particle_area;      // m^2 lumped area, only when wind is on (particle_count or 0)
  std::vector<Index> pinned;            // indices of pinned particles (pinned count)
  // attachments (core/attachments.h): pinned particles that follow a point bound to a collider mesh triangle
  std::vector<Index> attach_particle;   // ascending (attach count)
  std::vector<Index> attach_collider;   // into collision.colliders (attach count)
  std::vector<Index> attach_tri;        // collider mesh triangle, a row of collision.mesh_tri_index / 3 (attach count)
  std::vector<Vec3> attach_weight;      // barycentric weights of the particle's projection on it (attach count)
  std::vector<Real> attach_offset;      // signed distance along the triangle's unit normal, m (attach count)
  ParamField particle_thickness;        // collision thickness, m (particle_count, stride 0 when uniform)
  // stretch stiffness at each vertex (its <stiffness>, before the shear/bend scales), N/m: the spring that caps
  // the cloth-cloth repulsion (systems/collision/response.h) (particle_count, stride 0 when uniform)
  ParamField particle_stiffness;

  // --- springs
  Index spring_count = 0;
  std::vector<Index> spring_a;          // first particle (spring_count)
  std::vector<Index> spring_b;          // second particle (spring_count)
  std::vector<Real> spring_rest;        // rest length, m (spring_count)
  ParamField spring_ke;                 // stiffness, N/m (spring_count, stride 0 when uniform)
  ParamField spring_kd;                 // damping along the spring, N s/m (spring_count, stride 0 when uniform)
  std::array<Index, spring_kind_count> spring_kind_total{};  // springs of each SpringKind
  // largest allowed strain (|d| - rest)/rest, +inf where unlimited; only read when strain_limited
  ParamField spring_max_strain;         // (spring_count, stride 0 when uniform)
  bool strain_limited = false;          // some cloth sets maxStrain: the strain-limit stage runs
  // strain-limit schedule (core/spring_colours.h), only when strain_limited: the limited springs by colour; no
  // two springs of a colour share a particle, so a colour's projections run in parallel in any order
  std::vector<Index> spring_colour_offset;    // first entry of each colour in spring_colour_spring (colours + 1)
  std::vector<Index> spring_colour_spring;    // spring indices, colour by colour (limited spring count)
  // the schedule entries (indices into spring_colour_spring) at each particle, so a sweep can find the springs a
  // move makes worth projecting again
  std::vector<Index> particle_colour_offset;  // (particle_count + 1, or 0)
  std::vector<Index> particle_colour_entry;   // (2 x limited spring count)
  // long-range attachments (core/tethers.h), only for strain-limited cloths with pins: a free particle and its
  // nearest pin, which it may not leave by more than tether_length
  std::vector<Index> tether_particle;         // (tether_count)
  std::vector<Index> tether_pin;              // (tether_count)
  std::vector<Real> tether_length;            // (1 + maxStrain) x rest distance to the pin, m (tether_count)
  // incident springs of each particle: entry = spring index, ~index (negative) when the particle is spring_b;
  // built only when a kernel reads it (core/csr.h needs_particle_springs: not for the blocked layout alone)
  std::vector<Index> particle_spring_offset;  // (particle_count + 1, or 0)
  std::vector<Index> particle_spring_index;   // (2 * spring_count, or 0)
  SpringLayout spring_layout = SpringLayout::gather;  // build_model sets blocked where the chunks allow it
  // blocked layout (core/spring_chunks.h): chunks of consecutive springs, grouped into passes whose chunks touch
  // disjoint particle ranges, so one pass scatters into f in parallel without races (empty for other layouts)
  std::vector<Index> spring_chunk_offset;     // first spring of each chunk (chunk count + 1)
  std::vector<Index> spring_pass_offset;      // first entry of each pass in spring_pass_chunk (pass count + 1)
  std::vector<Index> spring_pass_chunk;       // chunk indices, pass by pass (chunk count)
  // particles each chunk opens (zeroes f before its springs) and closes (no spring touches them after it), as
  // [begin, end) pairs; the last slot holds the particles of no chunk (open/close_offset: chunk count + 2)
  std::vector<Index> spring_chunk_open_offset, spring_chunk_open_range;
  std::vector<Index> spring_chunk_close_offset, spring_chunk_close_range;
  // closing particles of its chunk final after each block of spring_block_size springs (a prefix of the chunk's
  // close ranges; ceil(spring_count / spring_block_size))
  std::vector<Index> spring_block_close;
  // blocked layout: external forces and the integrator's per-particle update run in the closing chunk, while
  // the particle is in cache (systems/forces.h); false runs them as separate passes (same bytes; for tests)
  bool fuse_particle_pass = true;

  // --- stitches: zero-rest-length seams (systems/stitch_forces.h), vertex stitch_a sewn to the point
  // (1 - w) x_b + w x_c; from the cloth OBJ's stitch records, <stitch> pairs and <cloth weld>
  Index stitch_count = 0;
  std::vector<Index> stitch_a, stitch_b, stitch_c;  // (stitch_count)
  std::vector<Real> stitch_w;                       // weight of stitch_c, in [0, 1] (stitch_count)
  std::vector<Real> stitch_ke;                      // stiffness, N/m (stitch_count)
  std::vector<Real> stitch_kd;                      // damping, N s/m (stitch_count)
  std::vector<Vec3> stitch_gap0;                    // gap x_a - ((1 - w) x_b + w x_c) at the start, m (stitch_count)
  std::vector<Real> stitch_close_time;              // s after the start when the sewing target reaches 0 (stitch_count)
  // incident stitches of each particle, entry = 3 * stitch + slot (0: a, 1: b, 2: c) (particle_count + 1 or 0)
  std::vector<Index> particle_stitch_offset, particle_stitch_index;

  // --- hinges: dihedral-angle bending (core/hinges.h, systems/bend_forces.h) of cloths with bending="dihedral";
  // the energy k (theta - theta0)^2 over each interior edge e0-e1 with opposite vertices o1, o2
  Index hinge_count = 0;
  std::vector<Index> hinge_e0, hinge_e1;  // the shared edge's ends (hinge_count)
  std::vector<Index> hinge_o1, hinge_o2;  // the vertices opposite it (hinge_count)
  std::vector<Real> hinge_rest_angle;     // theta0 from the rest mesh, rad (hinge_count)
  std::vector<Real> hinge_k;              // (D / 6) 3 |e|^2 / (A1 + A2) from the rest mesh, N m (hinge_count)
  // incident hinges of each particle, entry = 4 * hinge + slot (0: o1, 1: o2, 2: e0, 3: e1), in hinge order
  std::vector<Index> particle_hinge_offset, particle_hinge_index;  // (particle_count + 1, 4 * hinge_count; or 0)

  // --- triangles
  Index tri_count = 0;
  std::vector<Index> tri_index;               // (3 * tri_count)
  std::vector<Index> particle_tri_offset;     // incident triangles of each particle (particle_count + 1)
  std::vector<Index> particle_tri_index;      // (3 * tri_count)

  // --- forces applied to every particle
  Vec3 gravity{0, 0, 0};                // m/s^2, gravity + constant external acceleration
  Vec3 wind_velocity{0, 0, 0};          // m/s
  Real wind_strength = 0;               // kg/(m^2 s)
  Real air_damping = 0;                 // 1/s
  RandomForceDesc random;

  std::vector<ClothInfo> cloths;
  CollisionModel collision;             // empty unless the scene has colliders or self-collision

  bool needs_normals() const { return wind_strength != 0; }
};

// A particle's collider contact as the collide stage found it: the mean unit normal (zero: no contact), the
// collider's velocity at the contact, and the contact's Coulomb coefficient.
struct ContactHold {
  Vec3 normal = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  Real friction = 0;
};

struct State {
  std::vector<Vec3> x;  // positions, m (particle_count)
  std::vector<Vec3> v;  // velocities, m/s (particle_count)
  Real time = 0;        // s since the start frame
  std::int64_t step = 0;  // steps taken since the start frame (seeds the random forces)
  // Each particle's collider contact from the last collide stage: the implicit solve holds the particle on the
  // surface and rubs it with the contact's friction (systems/contact_filter.h). Empty until a step with the
  // filter on.
  std::vector<ContactHold> contact;
};

// The Cholesky preconditioner's run of every-solve refactorisations (systems/cholesky_preconditioner.h). Unlike the
// factor, which every frame drops, it carries across frames, so a checkpoint holds it (io/checkpoint.h).
struct CholeskyRenewal {
  int run = 0;   // length of the current run (0: none)
  int left = 0;  // refactorisations left in it
};

// The tightest CG tolerance solved with float spring blocks: 16 times their relative rounding, 2^-24.
inline constexpr Real kFloatBlockTolerance = 1e-6;

struct Workspace {
  // accumulated force, then acceleration (particle_count); the implicit step's multigrid cycle takes it as scratch
  // once the right-hand side has read it (systems/multigrid.h)
  std::vector<Vec3> f;
  std::vector<Vec3> stage_x, stage_v;  // RK4 stage state (particle_count, or 0 for other integrators)
  std::vector<Vec3> normal;        // unit vertex normals for wind and output (particle_count)
  std::vector<Real> stitch_rest, stitch_pull;  // each stitch's thread length and its shortening speed for the step
                                               // (stitch_count; systems/stitch_forces.h)
  // implicit integrator scratch (particle_count / spring_count, or 0 for other integrators)
  std::vector<Vec3> dv;  // the step's velocity change, summed over Newton solves (0 with one solve: it is cg_x)
  std::vector<Vec3> cg_x, cg_r, cg_p, cg_q;  // CG solution, residual, search; A p, then the preconditioner's z = B r
  std::vector<Sym3> cg_precond;    // inverse of the system's diagonal 3x3 block, 0 for pinned (particle_count)
  // h kd n n^T + h^2 dfa/dxb of each spring, symmetric (spring_count): in double with the Cholesky preconditioner
  // or a cg_tolerance below kFloatBlockTolerance, in float otherwise (core/math.h); the other is empty
  // (systems/implicit_system.h, with_spring_blocks).
  std::vector<Sym3> spring_block_f64;
  std::vector<Sym3f> spring_block_f32;
  std::vector<Sym3> stitch_kx, stitch_block;  // each stitch's -df/dg and h Kv + h^2 Kx (stitch_count)
  std::vector<Vec3> hinge_jac;  // each hinge's sqrt(2 k) d theta/dx at o1, o2, e0, e1 (4 * hinge_count; bend_forces.h)
  std::vector<Vec3> hinge_force;   // each hinge's forces on o1, o2, e0, e1, before the gather (4 * hinge_count)
  Multigrid multigrid;  // the multigrid preconditioner's levels (empty without it)
  // sparse Cholesky preconditioner (core/cholesky_factor.h; null without it): refactored when the step changes or
  // a solve does not converge in a few CG iterations with the factor it has (systems/cholesky_preconditioner.h)
  CholeskyFactorPtr cholesky;
  Real cholesky_h = 0;              // the step the factor was built for; 0 = no valid factor
  int cholesky_solves = 0;           // solves preconditioned by the current factor
  CholeskyRenewal cholesky_renewal;  // carried from frame to frame; the factor is not (cholesky_preconditioner.h)
  CollisionScratch collision;      // sized only when model.collision.enabled
};

// Sizes the workspace for a model stepped with these options; nothing inside step allocates afterwards.
Workspace make_workspace(const Model& model, const SimOptions& options);
// Rest state: the model's initial positions at rest.
State make_state(const Model& model, std::vector<Vec3> positions);

}  // namespace clothsim
