#pragma once
// What the collision stage needs: the collider table and cloth-side collision topology (immutable, in Model),
// and the per-step scratch (in Workspace). Empty for a scene without colliders and without a pair of cloths that
// collide (a cloth with itself under selfCollision, two cloths under clothCollision).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/scene_desc.h"

namespace clothsim {

struct Aabb {
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};
};

struct ColliderInfo {
  std::string name;
  ColliderShape shape = ColliderShape::mesh;
  Real friction = 0;
  Vec3 center{0, 0, 0};  // sphere, transformed
  Real radius = 0;
  Vec3 point{0, 0, 0};   // plane, transformed
  Vec3 normal{0, 1, 0};  // unit
  Index vertex_begin = 0, vertex_end = 0;  // rows of CollisionModel::mesh vertices (meshes only)
  Index tri_begin = 0, tri_end = 0;        // rows of mesh_tri_index / 3
  int first_frame = 0;                     // sequence: frame number of its first frame
  int frame_count = 0;                     // sequence: frames in the sequence (0 for a static mesh)
  int start_frame = 1;                     // sequence: the scene frame at t = 0 (the scene's startFrame)
  Real fps = 24;                           // sequence: frames per second it plays at (the scene's fps)
  bool closed = false;                     // every edge has two triangles: the inside test applies
};

// An AABB tree over a range of broad-phase slots, built once (core/bvh_build.cpp); node n: children
// node_child[2n], node_child[2n+1]; a leaf holds ~slot as a negative value in node_child[2n]. Nodes are in
// breadth-first order, level l at level_offset[l].
struct BvhTree {
  std::vector<Index> node_child;       // (2 * node count)
  std::vector<Index> level_offset;     // (levels + 1)
  Index node_count() const { return Index(node_child.size() / 2); }
};

// Where a sequence collider stands at time t (s since the start frame): between its stored frames f0 and f1,
// weight w on f1. From the step count, not a summed time, so every run lands on the same values.
struct FrameBlend {
  int f0 = 0, f1 = 0;
  Real w = 0;
};
inline FrameBlend frame_blend(const ColliderInfo& ci, Real t) {
  const Real local = std::clamp(ci.start_frame + t * ci.fps - ci.first_frame, Real(0), Real(ci.frame_count - 1));
  const int f0 = std::min(int(std::floor(local)), ci.frame_count - 1), f1 = std::min(f0 + 1, ci.frame_count - 1);
  return {f0, f1, local - f0};
}

struct CollisionModel {
  bool enabled = false;            // any collider, or cloth_contact
  bool cloth_contact = false;      // some pair of cloths (a cloth with itself included) is tested
  int iterations = 0;              // detection + response passes per step
  int zone_iterations = 0;         // rigid impact zone passes per step when crossings remain (0: none)
  BroadPhase broad_phase = BroadPhase::bvh;
  std::vector<ColliderInfo> colliders;

  // --- collider meshes, all colliders' vertices and triangles concatenated
  Index mesh_vertex_count = 0;
  std::vector<Vec3> mesh_x;          // static positions (a sequence's first frame), m (mesh_vertex_count)
  std::vector<Index> mesh_tri_index; // into mesh vertices (3 * mesh tris)
  std::vector<Index> mesh_tri_collider;  // owning collider (mesh tris)
  // Unique collider mesh edges (mesh vertex indices), reported by their lowest triangle like the cloth's.
  std::vector<Index> mesh_edge_a, mesh_edge_b, mesh_edge_first_tri;  // (mesh edge count)
  std::vector<Index> mesh_tri_edge;                                  // (3 * mesh tris)
  // Collider mesh vertices against cloth triangles: each vertex is reported by its lowest triangle, and its
  // outward normal (the sum of its triangles' normals) is gathered over its triangles, in triangle order.
  std::vector<Index> mesh_vertex_first_tri;                   // (mesh_vertex_count)
  std::vector<Index> mesh_vertex_tri_offset, mesh_vertex_tri;  // CSR (mesh_vertex_count + 1), (3 * mesh tris)
  bool animated = false;

  // --- cloth side
  std::vector<Index> particle_cloth;   // cloth of each particle (particle_count)
  Index cloth_count = 0;
  // 1 when cloth a's vertices and edges are tested against cloth b's triangles and edges: a == b under the
  // cloth's selfCollision, a != b when both have clothCollision (cloth_count * cloth_count, symmetric)
  std::vector<std::uint8_t> cloth_pair;
  std::vector<std::uint8_t> tri_contact;  // 1 when the triangle's cloth collides with some cloth (tri_count)
  // Unique cloth edges, for the edge-edge tests: those of tri_contact triangles, and, when a collider mesh
  // exists, those of every cloth (continuous edge-edge against the collider's edges).
  std::vector<Index> edge_a, edge_b;   // (edge count)
  std::vector<Index> edge_first_tri;   // lowest triangle holding the edge: the one that reports it (edge count)
  std::vector<std::uint8_t> edge_contact;  // 1 when the edge's cloth collides with some cloth (edge count)
  std::vector<Index> tri_edge;         // the three edges of each triangle holding listed edges, -1 otherwise (3 * tri_count)
  Real max_thickness = 0;              // m
  Real cell_size = 0;                  // spatial hash cell, m
  // Seams: the particles each particle is stitched to (Model::stitch_*), sorted. Like the two ends of a mesh edge
  // they are neighbours, not contacts: a sewn seam is not an intersection (docs/garments.md).
  std::vector<Index> seam_offset, seam_index;  // CSR (particle_count + 1, or 0 without stitches)

  // --- broad-phase primitives: the tri_contact cloth triangles (slots [0, cloth_prim_count)), then collider
  // triangles; prim id p < tri_count is cloth triangle p; p >= tri_count is collider triangle p - tri_count.
  std::vector<Index> prim;             // (prim count)
  Index cloth_prim_count = 0;
  // The two sides' broad phases are separate: the cloth's (the scene's hash, or cloth_tree) is rebuilt every
  // pass, the colliders' tree refitted once a step, when they move (systems/collision/broad_phase.h).
  BvhTree cloth_tree;                  // over the cloth slots; only for broadPhase="bvh"
  BvhTree collider_tree;               // over the collider slots; empty without collider meshes

  // Rigid impact zones run in this scene: a broad phase (continuous passes) and zone passes on.
  bool impact_zones() const { return !prim.empty() && iterations > 0 && zone_iterations > 0; }
  // Whether a vertex or edge of cloth a meets a triangle or edge of cloth b (the narrow phase's pair filter).
  bool cloths_collide(Index a, Index b) const { return cloth_pair[std::size_t(a) * cloth_count + b] != 0; }
  // Particles a and b are the same or sewn together by a stitch.
  bool joined(Index a, Index b) const {
    if (a == b) return true;
    if (seam_offset.empty()) return false;
    for (Index k = seam_offset[a]; k < seam_offset[a + 1]; ++k)
      if (seam_index[k] == b) return true;
    return false;
  }
  // Vertex i against the cloth triangle with corners tri[0..2]: their cloths meet and i is neither a corner nor
  // sewn to one.
  bool vertex_meets_cloth_triangle(Index i, const Index* tri) const {
    return cloths_collide(particle_cloth[i], particle_cloth[tri[0]]) && !joined(i, tri[0]) && !joined(i, tri[1]) &&
           !joined(i, tri[2]);
  }
  // Edges (a, b) and (p, q) share an end, or an end of one is sewn to an end of the other: not a contact pair.
  bool edges_adjacent(Index a, Index b, Index p, Index q) const {
    return joined(a, p) || joined(a, q) || joined(b, p) || joined(b, q);
  }
};

// The frames of one sequence collider a run holds at once: sequence frames first .. first + count - 1 (counted
// from 0, as FrameBlend counts them), transformed. The run reads them from disk ahead of the steps that blend
// them (sim/collider_track.h), so memory does not grow with the sequence's length.
inline constexpr int collider_window_frames = 4;
struct ColliderWindow {
  int first = 0, count = 0;
  std::vector<Vec3> x;  // m (collider_window_frames x the collider's vertices; the first count x vertices hold frames)
  bool holds(int f) const { return f >= first && f < first + count; }
};

// Collider mesh vertex v (a row of mesh_x) at a blend of frame_blend, read from the collider's window: its one
// position for a static mesh. The window must hold frames b.f0 and b.f1.
inline Vec3 collider_vertex(const CollisionModel& c, const ColliderInfo& ci, const ColliderWindow& w,
                            const FrameBlend& b, Index v) {
  if (ci.shape != ColliderShape::sequence) return c.mesh_x[v];
  const std::size_t nv = std::size_t(ci.vertex_end - ci.vertex_begin), k = std::size_t(v - ci.vertex_begin);
  return (1 - b.w) * w.x[std::size_t(b.f0 - w.first) * nv + k] + b.w * w.x[std::size_t(b.f1 - w.first) * nv + k];
}

// Spatial hash after Teschner et al. 2003: entries (bucket, prim, cell) scattered into contiguous bucket ranges.
struct HashScratch {
  Index table_size = 0;                 // a prime near twice the entry capacity
  Index entry_count = 0;
  Real inv_cell = 0;                    // 1 / this step's cell, m^-1: the model's cell_size unless enlarged
  std::vector<Index> prim_cells;        // cells of each prim, then its first entry (prim count + 1)
  std::vector<std::int64_t> entry_cell; // packed cell coordinates, in bucket order (entry capacity)
  std::vector<Index> entry_prim;        // (entry capacity)
  std::vector<Index> scatter_prim;      // unsorted entries (entry capacity)
  std::vector<std::int64_t> scatter_cell;
  std::vector<Index> scatter_bucket;
  std::vector<Index> bucket_offset;     // (table_size + 1)
  std::vector<Index> bucket_fill;       // (table_size)
};

// Where a set of cloth particles can be met: marked cells of a uniform grid (systems/collision/reach_grid.h).
struct ReachGrid {
  Real inv_cell = 0;                // 1 / cell side, m^-1; the side is the reach
  bool everywhere = false;          // a path beyond the representable cells: every box is near
  std::vector<std::int64_t> cells;  // packed cell coordinates (systems/collision/spatial_hash.h), sorted, unique
};

// What the impact zones did, summed over steps (--stats writes them per frame).
struct ZoneFigures {
  std::int64_t steps = 0;       // steps that ran the zones (crossings left after the continuous passes)
  std::int64_t passes = 0;      // detection passes of those steps
  std::int64_t zones = 0;       // zones at the end of those steps
  std::int64_t zone_nodes = 0;  // nodes in them (cloth vertices and collider vertices)
  std::int64_t largest = 0;     // most nodes in one zone
  std::int64_t unresolved = 0;  // steps that stopped with pairs left (the cap, or a pass that merged nothing)

  void add(const ZoneFigures& o) {
    steps += o.steps;
    passes += o.passes;
    zones += o.zones;
    zone_nodes += o.zone_nodes;
    largest = std::max(largest, o.largest);
    unresolved += o.unresolved;
  }
};

// Rigid impact zones (Provot 1997; Bridson, Fedkiw & Anderson 2002 §6.3; systems/collision/impact_zones.h). A node is
// a cloth particle (0 .. particle_count - 1) or a collider mesh vertex (particle_count + its index). Every array
// holds one entry per node, so no pass can find more zones or members than there is room for: nothing to overflow.
// Sized only when the scene has a broad phase and zones are on.
struct ZoneScratch {
  std::vector<Index> parent;         // union-find parent; a zone's root is its smallest node (node count)
  std::vector<std::uint8_t> flag;    // zone_member: in a zone this step; zone_touched: in a pair of this pass
  std::vector<Index> slot;           // the zone number of a root whose zone this pass refits, else -1
  std::vector<Index> offset;         // CSR of the refitted zones' members, ascending: (node count + 1)
  std::vector<Index> member;         // (node count)
  Index zone_count = 0;              // zones refitted by this pass
  // The later passes' reach: (root, particle) of every cloth particle in a zone, and round each root's members a
  // box that every element able to meet one of them overlaps (reserved to the particle count).
  std::vector<std::array<Index, 2>> reach;
  std::vector<Aabb> reach_box;
};

// One pair a detection pass found, for the response to consume (systems/collision/contacts.h).
enum class ContactKind : std::uint8_t {
  vertex_triangle,  // a: cloth vertex, b: prim (cloth or collider triangle); w: the triangle's barycentrics
  cloth_edges,      // a, b: cloth edges; w[0], w[1]: the closest points' parameters s, t along them
  collider_vertex,  // a: cloth triangle, b: collider vertex; w: the triangle's barycentrics
  collider_edge,    // a: cloth edge, b: collider edge; w[0], w[1]: s, t
};
struct Contact {
  ContactKind kind;
  Index a, b;
  Real w[3];
  Vec3 n;  // unit direction the pair must separate along, towards a's side (b's for collider_vertex)
  Real d;  // end-of-step distance along n, m (negative: crossed)
};

// One walk kind's candidate lists (systems/collision/candidate_cache.h): each cloth element's broad-phase slots,
// in the trees' order, gathered per fixed block of elements; end[e] is where element e's slots end in its block.
struct CandidateLists {
  std::vector<std::vector<Index>> block;
  std::vector<Index> end;  // (elements)
};
struct CandidateCache {
  bool on = false;                // lists made for this step's broad phase and still usable
  const Vec3* in_ref = nullptr;   // the start-of-step positions they were made for
  std::vector<Vec3> x_ref;        // the end-of-step positions they were made for (particle_count)
  Real margin = 0;                // each query was grown by twice this, m
  // Cloth slots whose boxes now come from a corner more than the margin from x_ref: walks test them apart.
  std::vector<Index> runaway;
  std::vector<std::uint8_t> is_runaway;  // (cloth slot count)
  CandidateLists vertex, triangle, edge;
};

struct CollisionScratch {
  std::vector<Vec3> collider_x0, collider_x1;  // collider mesh vertices at the start and end of the step
  // The animated colliders' frames the steps read, filled by the frame loop (sim/collider_track.h); one per
  // collider, sized for sequences only (colliders)
  std::vector<ColliderWindow> collider_frames;
  std::vector<Aabb> prim_box;           // swept, thickness-inflated box per prim (prim count)
  std::vector<Aabb> cloth_node_box;     // cloth_tree's node boxes (its node count)
  std::vector<Aabb> collider_node_box;  // collider_tree's node boxes (its node count)
  Aabb query_bounds;                    // union of the cloth vertices' swept boxes
  HashScratch hash;
  CandidateCache candidates;
  // Per-particle accumulators in fixed point (fixed_scale units): integer sums are exact and associative, so
  // the averaged response is the same bytes whatever the order the threads add in.
  std::vector<std::int64_t> acc_dv, acc_dx;  // (3 * particle_count)
  std::vector<std::int32_t> acc_count;       // (particle_count)
  // The implicit solve's contact filter (systems/contact_filter.h), sized only when it is on: per particle, the
  // fixed-point sums of its collider contacts' unit normals, collider velocities and friction coefficients over the
  // collide stage's proximity passes (7 * particle_count), and their count (particle_count); the normal each
  // particle is held along in the solve under way, zero where free; the normal impulse its hold has given it, and
  // n . b of the solve under way (particle_count).
  std::vector<std::int64_t> acc_hold;
  std::vector<std::int32_t> acc_hold_count;
  std::vector<Vec3> filter_normal;
  std::vector<Real> held_impulse, held_rhs;
  // n . x of each particle the collide stage left on a collider, n its contact's normal: the plane the strain
  // limit after the collide stage keeps it in front of (systems/strain_limit.h; particle_count, with the filter).
  std::vector<Real> contact_offset;
  // Where the collide stage left each particle (particle_count, with contact_offset): a vertex the strain limit's
  // rounds after it carry into a collider goes back along its way towards there (systems/collision/collider_guard.h).
  std::vector<Vec3> collided_x;
  // The cloth-cloth pairs the collide stage left within the thickness, sorted: the strain limit after the
  // collide stage keeps each at least as far apart as the stage left it (systems/collision/cloth_holds.h).
  std::vector<Contact> cloth_holds;
  // The pairs of the latest detection pass (systems/collision/contacts.h): [0, contact_count) of a buffer that
  // grows to the most one pass has found
  std::vector<Contact> contacts;
  Index contact_count = 0;
  // 1 for the cloth particles of the pairs the latest continuous pass found: the next pass and the impact zones'
  // first pass test only pairs with one of them (particle_count).
  std::vector<std::uint8_t> crossed;
  ReachGrid crossed_reach;  // where those particles can be met (systems/collision/reach_grid.h)
  ZoneScratch zones;
  // Cloth particles found inside a closed collider mesh: that collider, or -1 (particle_count); filled by the
  // first step this workspace takes (systems/collision/push_out.h).
  std::vector<std::int32_t> deep_collider;
  bool deep_scanned = false;
};

}  // namespace clothsim
