#pragma once
// A scene as written in the XML file: paths and numbers, no derived quantities.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"

namespace clothsim {

enum class Integrator { euler, symplectic, rk4, implicit };
// Preconditioner of the implicit step's CG (systems/multigrid.h; docs/stability.md).
enum class Preconditioner { jacobi, multigrid, cholesky };
// Broad phase of the collision stage (docs/performance.md, "Spatial hash against BVH", compares them).
enum class BroadPhase { hash, bvh };
// A cloth's bending: bend/flex springs (the seeds' model) or dihedral-angle hinges (core/hinges.h; docs/model.md).
enum class Bending { springs, dihedral };

// The names the scene file, the reports and the studies use: one table per enum, in the enum's order, so a new
// value is added in one place.
inline constexpr std::array<const char*, 4> integrator_names{"euler", "symplectic", "rk4", "implicit"};
inline constexpr std::array<const char*, 3> preconditioner_names{"jacobi", "multigrid", "cholesky"};
inline constexpr std::array<const char*, 2> broad_phase_names{"hash", "bvh"};
inline constexpr std::array<const char*, 2> bending_names{"springs", "dihedral"};
inline const char* integrator_name(Integrator i) { return integrator_names[std::size_t(i)]; }
inline const char* preconditioner_name(Preconditioner p) { return preconditioner_names[std::size_t(p)]; }
// The value a table names `name`; false (out unchanged) when it names none.
template <class Enum, std::size_t N>
bool enum_from_name(const std::array<const char*, N>& names, std::string_view name, Enum& out) {
  for (std::size_t k = 0; k < N; ++k)
    if (name == names[k]) { out = Enum(k); return true; }
  return false;
}

struct SimulationDesc {
  Real timestep = 0.001;       // s, requested; the step used divides a frame evenly (steps_per_frame)
  // timestep="auto": the step is chosen from the stability estimate and adapted during the run
  // (systems/auto_step.h, sim/frame_stepper.h); step_safety is the fraction of the estimated limit taken, min_timestep the
  // smallest step before the run stops as diverged (0: the chosen step / 1024)
  bool timestep_auto = false;
  Real step_safety = 0.7;
  Real min_timestep = 0;
  Real fps = 24;               // frames per second of the output sequence
  int start_frame = 1;         // frame written from the initial state
  int end_frame = 48;          // last frame written
  Integrator integrator = Integrator::symplectic;
  Vec3 gravity{0, -9.81, 0};   // m/s^2
  int collision_iterations = 2;
  // rigid impact zone passes per step after the continuous pass (Bridson et al. 2002 §6.3); 0: none
  int impact_zone_iterations = 16;
  // implicit integrator (Baraff & Witkin 1998): CG stops at |r| <= cg_tolerance |b| or after cg_max_iterations;
  // newton_iterations linear solves per step (1 = Baraff & Witkin's single linearised solve)
  Real cg_tolerance = 1e-6;
  int cg_max_iterations = 1000;
  int newton_iterations = 1;
  Preconditioner preconditioner = Preconditioner::multigrid;
  bool contact_filter = true;  // implicit: particles touching a collider are held on it in the solve
  BroadPhase broad_phase = BroadPhase::bvh;
  int checkpoint_every = 0;    // frames between checkpoints (and one at the end); 0: none (io/checkpoint.h)
  bool cloth_collision = true; // different cloths collide with each other (a cloth with itself: selfCollision)
};

struct RandomForceDesc {
  Real amplitude = 0;          // m/s^2, largest random acceleration per axis
  Real period = 0.5;           // s, time between the gust field's lattice nodes (systems/random_force.h)
  Real cell_size = 0.5;        // m, space between the gust field's lattice nodes
  std::uint64_t seed = 1;
  std::array<bool, 6> allow{true, true, true, true, true, true};  // negX posX negY posY negZ posZ
};

struct ForcesDesc {
  Vec3 external_acceleration{0, 0, 0};  // m/s^2, added to gravity
  Vec3 wind_velocity{0, 0, 0};          // m/s
  Real wind_strength = 0;               // kg/(m^2 s): force per unit area per unit normal relative speed
  RandomForceDesc random;
  Real air_damping = 0;                 // 1/s: acceleration -c v on every particle
};

struct TransformDesc {
  Vec3 translate{0, 0, 0};  // m
  Vec3 rotate{0, 0, 0};     // degrees about X, then Y, then Z
  Vec3 scale{1, 1, 1};
};

// A parameter painted as a grey-scale image: value = lerp(min, max, grey at the vertex's UV) (docs/maps.md).
struct ParamMapDesc {
  std::string path;           // image, resolved against the scene folder; empty when the value is uniform
  Real min = 0, max = 0;
  int line = 0;               // line of the element, for error messages
  bool mapped() const { return !path.empty(); }
};

// <attach>: cloth vertices bound to the nearest triangle of a mesh collider at the first frame, moving with it
// (core/attachments.h).
struct AttachDesc {
  std::string collider;         // name of a <static> collider
  std::vector<Index> vertices;  // vertex indices, counted from 0
  ParamMapDesc map;             // vertices whose grey level is above 0.5 (min 0, max 1), when mapped
  int line = 0;                 // line of the element, for error messages
};

struct ClothDesc {
  std::string name;
  int line = 0;               // line of the <cloth> element, for error messages
  std::string obj;            // mesh path (resolved against the scene folder), or empty for a grid
  int grid_nx = 0, grid_ny = 0;
  Real grid_w = 1, grid_h = 1;
  std::string save_dir = "out";
  std::string save_name;
  std::string texture;        // colour texture, passed through to the output
  TransformDesc transform;
  Real friction = 0.3;
  Real restitution = 0;
  bool self_collision = false;  // with itself: off by default, it is expensive
  bool cloth_collision = true;  // with the other cloths, when <simulation clothCollision> is on too
  Real density = 0.2;         // kg/m^2
  Real stiffness = 1000;      // N/m per spring
  Real shear_scale = 1;       // shear springs: stiffness * shear_scale (grids)
  Real bend_scale = 1;        // bend/flex springs: stiffness * bend_scale
  Bending bending = Bending::springs;  // dihedral: hinges instead of bend/flex springs
  Real bend_modulus = 1e-5;   // N m, bending modulus D of the dihedral hinges (plate rigidity, per unit width)
  Real damping = 0.1;         // N s/m per spring, on the relative speed along it
  Real thickness = 0.005;     // m
  std::vector<Index> pins;    // vertex indices held fixed
  Real max_strain = 0;        // Provot 1995 strain limit (|d| - rest)/rest, 0 for none
  bool mass_per_vertex = false;  // <mass> given: kg per vertex instead of density lumped by area
  Real mass = 0;              // kg per vertex, when mass_per_vertex and not mapped
  std::vector<Index> stitch_pairs;  // <stitch vertices="i j ...">: vertex pairs sewn together (0-based)
  Real weld = 0;              // m: boundary vertices of different pieces closer than this are sewn; 0 for none
  Real sew_speed = 0.2;       // m/s: how fast a stitch's target gap shrinks to zero (systems/stitch_forces.h)
  ParamMapDesc density_map, mass_map, stiffness_map, damping_map, thickness_map, pins_map;
  std::vector<AttachDesc> attach;
  std::string rest;           // rest-shape mesh (resolved), or empty: rest lengths from the cloth's own mesh
};

// A collider: <static obj|sequence>, <sphere> or <plane>. Meshes are one-sided: the outside is where the
// counter-clockwise triangle normals point.
enum class ColliderShape { mesh, sequence, sphere, plane };
struct ColliderDesc {
  std::string name;
  int line = 0;                 // line of the element, for error messages
  ColliderShape shape = ColliderShape::mesh;
  std::string obj;              // mesh path (resolved against the scene folder)
  std::string sequence;         // frame path pattern, '#' run = zero-padded frame number (resolved)
  Vec3 center{0, 0, 0};         // sphere centre, m
  Real radius = 1;              // sphere radius, m
  Vec3 point{0, 0, 0};          // a point of the plane, m
  Vec3 normal{0, 1, 0};         // plane normal, pointing to the free side
  Real friction = 0.3;          // Coulomb coefficient; a contact uses the geometric mean with the cloth's
  TransformDesc transform;
};

struct SceneDesc {
  std::string path;           // the scene file
  std::string base_dir;       // folder relative paths are resolved against
  SimulationDesc simulation;
  ForcesDesc forces;
  std::vector<ClothDesc> cloths;
  std::vector<ColliderDesc> colliders;
};

// Steps per frame: ceil(1/(fps*timestep)) with a relative tolerance, so 1/(24*(1/240)) is 10, not 11.
int steps_per_frame(const SimulationDesc& sim);

}  // namespace clothsim
