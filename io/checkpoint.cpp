#include "io/checkpoint.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/text_file.h"

namespace clothsim::io {
namespace {

// Layout (native little-endian, 8-byte fields):
//   "CLOTHCKP" | u32 version | u32 first output frame | u64 fingerprint | i64 frame | i64 step | f64 time | u64 n
//   | u64 c (0 or n) | i32 Cholesky renewal run | i32 refactorisations left in it | f64 x[3n] | f64 v[3n]
//   | f64 contact[7c] (normal, collider velocity, friction)
//   | u64 hash64 of every byte before it
static_assert(std::endian::native == std::endian::little, "checkpoints are stored little-endian");
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
constexpr char magic[8] = {'C', 'L', 'O', 'T', 'H', 'C', 'K', 'P'};
constexpr std::size_t header_bytes = 8 + 4 + 4 + 8 * 6 + 4 + 4;
static_assert(sizeof(ContactHold) == 7 * sizeof(double), "a contact is written as 7 doubles");

template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <class T>
T get(std::string_view bytes, std::size_t& pos) {
  T value;
  std::memcpy(&value, bytes.data() + pos, sizeof(T));
  pos += sizeof(T);
  return value;
}

}  // namespace

std::uint64_t hash64(std::string_view bytes, std::uint64_t h) {
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

namespace {

template <class T>
std::uint64_t hash_array(const std::vector<T>& v, std::uint64_t h) {
  const std::uint64_t n = v.size();  // the length too: [1 2][3] and [1][2 3] differ
  h = hash64(std::string_view(reinterpret_cast<const char*>(&n), sizeof n), h);
  return hash64(std::string_view(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)), h);
}

std::uint64_t hash_mesh(const MeshData& m, std::uint64_t h) {
  h = hash_array(m.tri_uv, hash_array(m.tri_index, hash_array(m.uvs, hash_array(m.positions, h))));
  h = hash_array(m.stitch_w, hash_array(m.stitch_c, hash_array(m.stitch_b, hash_array(m.stitch_a, h))));
  h = hash_array(m.rest_positions, h);
  const VertexParams& p = m.params;
  return hash_array(p.pinned, hash_array(p.thickness, hash_array(p.damping, hash_array(p.stiffness,
         hash_array(p.mass, hash_array(p.density, h))))));
}

}  // namespace

std::uint64_t inputs_fingerprint(std::string_view scene_text, std::span<const MeshData> cloths) {
  std::uint64_t h = hash64(scene_text);
  for (const MeshData& m : cloths) h = hash_mesh(m, h);
  return h;
}

std::uint64_t fingerprint_mesh(const MeshData& mesh, std::uint64_t h) { return hash_mesh(mesh, h); }

std::uint64_t scene_fingerprint(std::uint64_t inputs, Real dt, std::span<const Vec3> x0) {
  std::uint64_t h = hash64(std::string_view(reinterpret_cast<const char*>(&inputs), sizeof inputs));
  h = hash64(std::string_view(reinterpret_cast<const char*>(x0.data()), x0.size_bytes()), h);
  return hash64(std::string_view(reinterpret_cast<const char*>(&dt), sizeof dt), h);
}

std::string encode_checkpoint(const Checkpoint& c) {
  const std::uint64_t n = c.state.x.size(), contacts = c.state.contact.size();
  std::string out;
  out.reserve(header_bytes + 2 * n * sizeof(Vec3) + contacts * sizeof(ContactHold) + 8);
  out.append(magic, sizeof magic);
  put(out, checkpoint_version);
  put(out, std::uint32_t(c.first_output));
  put(out, c.fingerprint);
  put(out, std::int64_t{c.frame});
  put(out, std::int64_t{c.state.step});
  put(out, double{c.state.time});
  put(out, n);
  put(out, contacts);
  put(out, std::int32_t(c.cholesky_renewal.run));
  put(out, std::int32_t(c.cholesky_renewal.left));
  out.append(reinterpret_cast<const char*>(c.state.x.data()), n * sizeof(Vec3));
  out.append(reinterpret_cast<const char*>(c.state.v.data()), n * sizeof(Vec3));
  if (contacts > 0) out.append(reinterpret_cast<const char*>(c.state.contact.data()), contacts * sizeof(ContactHold));
  put(out, hash64(out));
  return out;
}

Checkpoint decode_checkpoint(const std::string& path, std::string_view bytes) {
  if (bytes.size() < header_bytes + 8 || std::memcmp(bytes.data(), magic, sizeof magic) != 0)
    throw Error(path, "not a clothsim checkpoint (bad header or truncated); expected a file written by clothsim run");
  std::size_t pos = sizeof magic;
  const auto version = get<std::uint32_t>(bytes, pos);
  if (version != checkpoint_version)
    throw Error(path, "checkpoint format version " + std::to_string(version) + "; expected version " +
                          std::to_string(checkpoint_version));
  const auto first_output = get<std::uint32_t>(bytes, pos);
  Checkpoint c;
  c.fingerprint = get<std::uint64_t>(bytes, pos);
  const auto frame = get<std::int64_t>(bytes, pos);
  c.state.step = get<std::int64_t>(bytes, pos);
  c.state.time = get<double>(bytes, pos);
  const auto n = get<std::uint64_t>(bytes, pos);
  const auto contacts = get<std::uint64_t>(bytes, pos);
  c.cholesky_renewal.run = get<std::int32_t>(bytes, pos);
  c.cholesky_renewal.left = get<std::int32_t>(bytes, pos);
  // Size is checked before anything is allocated, so a hostile count cannot exhaust memory.
  const std::uint64_t payload = bytes.size() - header_bytes - 8;
  if (n > payload / (2 * sizeof(Vec3)) || (contacts != 0 && contacts != n) ||
      header_bytes + 2 * n * sizeof(Vec3) + contacts * sizeof(ContactHold) + 8 != bytes.size())
    throw Error(path, "checkpoint is truncated or has trailing bytes; expected " + std::to_string(n) +
                          " particles' positions and velocities, and their collider contacts or none");
  const std::size_t end = bytes.size() - 8;
  std::size_t tail = end;
  if (get<std::uint64_t>(bytes, tail) != hash64(bytes.substr(0, end)))
    throw Error(path, "checkpoint checksum mismatch (the file is corrupted); expected an intact checkpoint");
  if (frame < 0 || frame > 1000000) throw Error(path, "checkpoint frame out of range");
  if (c.cholesky_renewal.left < 0 || c.cholesky_renewal.left > c.cholesky_renewal.run)
    throw Error(path, "checkpoint's Cholesky renewal counts out of range; expected 0 <= left <= run");
  c.frame = static_cast<int>(frame);
  if (first_output > std::uint32_t(frame)) throw Error(path, "checkpoint's first written frame is after its frame");
  c.first_output = static_cast<int>(first_output);
  c.state.x.resize(n);
  c.state.v.resize(n);
  std::memcpy(static_cast<void*>(c.state.x.data()), bytes.data() + pos, n * sizeof(Vec3));
  std::memcpy(static_cast<void*>(c.state.v.data()), bytes.data() + pos + n * sizeof(Vec3), n * sizeof(Vec3));
  c.state.contact.resize(contacts);
  if (contacts > 0)  // memcpy's pointers must not be null, even for no bytes
    std::memcpy(static_cast<void*>(c.state.contact.data()), bytes.data() + pos + 2 * n * sizeof(Vec3),
                contacts * sizeof(ContactHold));
  return c;
}

std::string checkpoint_path(const std::string& dir, const std::string& stem, int frame) {
  char num[16];
  std::snprintf(num, sizeof num, "%04d", frame);
  return (dir.empty() ? std::string(".") : dir) + "/" + stem + "." + num + ".ckpt";
}

namespace {

// Frames of the checkpoints of `stem` in `dir`, newest first.
std::vector<int> checkpoint_frames(const std::string& dir, const std::string& stem) {
  std::vector<int> frames;
  std::error_code ec;
  const std::string prefix = stem + ".", suffix = ".ckpt";
  for (const auto& e : std::filesystem::directory_iterator(dir.empty() ? "." : dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const char* b = name.data() + prefix.size();
    const char* end = name.data() + name.size() - suffix.size();
    int frame = 0;
    auto [p, err] = std::from_chars(b, end, frame);
    if (err == std::errc() && p == end && end - b >= 4) frames.push_back(frame);
  }
  std::sort(frames.rbegin(), frames.rend());
  return frames;
}

}  // namespace

void write_checkpoint(const std::string& dir, const std::string& stem, const Checkpoint& c, int keep) {
  write_file_atomic(checkpoint_path(dir, stem, c.frame), encode_checkpoint(c));
  const std::vector<int> frames = checkpoint_frames(dir, stem);
  for (std::size_t i = std::max(keep, 1); i < frames.size(); ++i)
    std::remove(checkpoint_path(dir, stem, frames[i]).c_str());
}

void remove_checkpoints_after(const std::string& dir, const std::string& stem, int frame) {
  for (const int f : checkpoint_frames(dir, stem))
    if (f > frame) std::remove(checkpoint_path(dir, stem, f).c_str());
}

std::optional<Checkpoint> find_latest_checkpoint(const std::string& dir, const std::string& stem,
                                                 std::uint64_t fingerprint, Index particle_count, int first_output,
                                                 std::vector<std::string>& warnings) {
  for (const int frame : checkpoint_frames(dir, stem)) {
    const std::string path = checkpoint_path(dir, stem, frame);
    try {
      Checkpoint c = decode_checkpoint(path, read_text_file(path, "a clothsim checkpoint"));
      if (c.fingerprint != fingerprint || c.state.x.size() != std::size_t(particle_count))
        throw Error(path, "checkpoint belongs to another scene (the scene file or its meshes changed)");
      if (c.frame != frame) throw Error(path, "checkpoint holds frame " + std::to_string(c.frame));
      // Frames before the checkpoint's run began writing were never written (run --frames A:B).
      if (c.first_output > first_output)
        throw Error(path, "checkpoint's run wrote frames " + std::to_string(c.first_output) + ".." +
                              std::to_string(c.frame) + " only; this run needs frames from " +
                              std::to_string(first_output));
      return c;
    } catch (const Error& e) {
      warnings.push_back(std::string(e.what()) + "; skipped");
    }
  }
  return std::nullopt;
}

}  // namespace clothsim::io
