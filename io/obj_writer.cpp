#include "io/obj_writer.h"

#include <charconv>
#include <cstdio>

#include "io/atomic_file.h"

namespace clothsim::io {
namespace {

// Appends numbers with std::to_chars: locale-independent, shortest form at the given significant digits. The
// text goes to `sink` in pieces of about piece_bytes, at line ends, so a frame is never held whole (a 1M-particle
// frame is about 130 MB of text).
class ObjText {
 public:
  static constexpr std::size_t piece_bytes = std::size_t(1) << 20;
  explicit ObjText(const PieceWriter& sink) : sink_(sink) { s_.reserve(piece_bytes + 256); }
  void tag(const char* t) { s_ += t; }
  void number(double x, int digits) {
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, x == 0 ? 0.0 : x, std::chars_format::general, digits);
    s_ += ' ';
    s_.append(buf, r.ptr);
  }
  void integer(long long i) {
    char buf[24];
    auto r = std::to_chars(buf, buf + sizeof buf, i);
    s_.append(buf, r.ptr);
  }
  void raw(std::string_view t) { s_ += t; }
  void end_line() {
    s_ += '\n';
    if (s_.size() >= piece_bytes) flush();
  }
  void flush() {
    if (!s_.empty()) sink_(s_);
    s_.clear();
  }

 private:
  std::string s_;
  const PieceWriter& sink_;
};


constexpr int position_digits = 9;
constexpr int uv_digits = 9;
constexpr int normal_digits = 7;

void emit_frame(const Model& model, const ClothInfo& cloth, const std::string& save_name, std::span<const Vec3> x,
                std::span<const Vec3> normal, int frame, const PieceWriter& sink) {
  ObjText out(sink);
  out.raw("# clothsim frame ");
  out.integer(frame);
  out.raw("\n");
  // A textured cloth references its material (io/mtl_writer), written once beside the frames.
  const bool textured = !cloth.texture.empty();
  if (textured) out.raw("mtllib " + save_name + ".mtl\n");
  out.raw("o ");
  out.raw(cloth.name.empty() ? std::string_view("cloth") : std::string_view(cloth.name));
  out.raw("\n");
  for (Index i = cloth.particle_begin; i < cloth.particle_end; ++i) {
    out.tag("v");
    for (int k = 0; k < 3; ++k) out.number(x[i][k], position_digits);
    out.end_line();
  }
  for (const Vec2& uv : cloth.uvs) {
    out.tag("vt");
    out.number(uv[0], uv_digits);
    out.number(uv[1], uv_digits);
    out.end_line();
  }
  for (Index i = cloth.particle_begin; i < cloth.particle_end; ++i) {
    out.tag("vn");
    for (int k = 0; k < 3; ++k) out.number(normal[i][k], normal_digits);
    out.end_line();
  }
  const bool uvs = !cloth.tri_uv.empty() || cloth.uv_per_vertex;
  if (textured) out.raw("usemtl " + save_name + "\n");
  for (Index t = cloth.tri_begin; t < cloth.tri_end; ++t) {
    out.tag("f");
    for (int k = 0; k < 3; ++k) {
      const long long v = model.tri_index[3 * std::size_t(t) + k] - cloth.particle_begin + 1;
      out.raw(" ");
      out.integer(v);
      out.raw("/");
      if (cloth.uv_per_vertex) out.integer(v);
      else if (uvs) out.integer(cloth.tri_uv[3 * std::size_t(t - cloth.tri_begin) + k] + 1);
      out.raw("/");
      out.integer(v);
    }
    out.end_line();
  }
  out.flush();
}

}  // namespace

std::string frame_path(const std::string& dir, const std::string& save_name, int frame) {
  char num[16];
  std::snprintf(num, sizeof num, "%04d", frame);
  return (dir.empty() ? std::string(".") : dir) + "/" + save_name + "." + num + ".obj";
}

std::string format_frame(const Model& model, const ClothInfo& cloth, const std::string& save_name,
                         std::span<const Vec3> x, std::span<const Vec3> normal, int frame) {
  std::string text;
  text.reserve(std::size_t(cloth.particle_end - cloth.particle_begin) * 90 +
               std::size_t(cloth.tri_end - cloth.tri_begin) * 40 + 256);
  emit_frame(model, cloth, save_name, x, normal, frame, [&](std::string_view piece) { text += piece; });
  return text;
}

void write_frame(const std::string& path, const Model& model, const ClothInfo& cloth, const std::string& save_name,
                 std::span<const Vec3> x, std::span<const Vec3> normal, int frame) {
  write_file_atomic(path,
                    [&](const PieceWriter& write) { emit_frame(model, cloth, save_name, x, normal, frame, write); });
}

}  // namespace clothsim::io
