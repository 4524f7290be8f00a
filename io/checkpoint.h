#pragma once
// Checkpoints of a run: the whole State (positions, velocities, time, step counter, and the collider contact normals
// the implicit solve holds) after a frame, and the Cholesky preconditioner's renewal run, so a killed run resumes
// and recomputes the later frames bit for bit. The random forces are counter-based on the step index
// (systems/random_force.h), so the step counter is their whole state; the Cholesky factor is dropped at every
// frame's start (sim/simulation.cpp), and nothing else carries over between frames. A checkpoint is written
// atomically and carries a format version, a fingerprint of the scene it came from and a 64-bit checksum over
// everything before it, so a truncated or corrupted file is recognised.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/build_collision.h"
#include "core/mesh_data.h"
#include "core/model.h"

namespace clothsim::io {

inline constexpr std::uint32_t checkpoint_version = 4;

struct Checkpoint {
  std::uint64_t fingerprint = 0;  // of the scene (see scene_fingerprint): a checkpoint of another scene is refused
  int frame = 0;                  // last frame whose output was written before this checkpoint
  int first_output = 0;           // first frame the run wrote: the checkpoint vouches for frames first_output..frame
  State state;
  CholeskyRenewal cholesky_renewal;  // the workspace's, after the frame
};

// FNV-1a, 64-bit: catches truncation and any flipped byte with probability 1 - 2^-64; not cryptographic.
std::uint64_t hash64(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ULL);

// Fingerprint of every input's content as read: the scene file's text and each cloth mesh (positions, UVs,
// triangles and the parameters sampled from its maps), then each collider mesh frame chained on with
// fingerprint_mesh as io::read_colliders reads them (sim/load_scene.cpp).
std::uint64_t inputs_fingerprint(std::string_view scene_text, std::span<const MeshData> cloths);
std::uint64_t fingerprint_mesh(const MeshData& mesh, std::uint64_t h);

// Fingerprint of what a run depends on: its inputs (inputs_fingerprint), the built model's initial positions
// (which cover the transforms) and the step size dt.
std::uint64_t scene_fingerprint(std::uint64_t inputs, Real dt, std::span<const Vec3> x0);

std::string encode_checkpoint(const Checkpoint& c);
// Throws Error(path, ...) naming what is wrong: magic, version, size, checksum.
Checkpoint decode_checkpoint(const std::string& path, std::string_view bytes);

// <dir>/<stem>.<frame, 4 digits>.ckpt
std::string checkpoint_path(const std::string& dir, const std::string& stem, int frame);

// Writes the checkpoint of `frame` atomically, then deletes all but the newest `keep` checkpoints of `stem`
// (the previous one stays, for when the newest is later found corrupted).
void write_checkpoint(const std::string& dir, const std::string& stem, const Checkpoint& c, int keep = 2);

// Deletes the checkpoints of `stem` after `frame`: a run starting (or resuming) there replaces them.
void remove_checkpoints_after(const std::string& dir, const std::string& stem, int frame);

// The newest checkpoint of `stem` in `dir` that decodes, matches `fingerprint` and `particle_count` and whose
// run wrote every frame from `first_output` on; each newer one that does not is reported through `warnings`
// (one line each) and skipped. nullopt when none is valid.
std::optional<Checkpoint> find_latest_checkpoint(const std::string& dir, const std::string& stem,
                                                 std::uint64_t fingerprint, Index particle_count, int first_output,
                                                 std::vector<std::string>& warnings);

}  // namespace clothsim::io
