#include "io/obj_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <tiny_obj_loader.h>

#include "core/error.h"
#include "core/limits.h"
#include "io/obj_stitches.h"
#include "io/text_file.h"

namespace clothsim::io {
namespace {

bool starts_with_tag(std::string_view line, std::string_view tag) {
  return line.size() > tag.size() && line.substr(0, tag.size()) == tag &&
         (line[tag.size()] == ' ' || line[tag.size()] == '\t');
}

// tinyobjloader stores a face's corner count in an unsigned char: a face of 256 or more corners would be
// miscounted, so it is refused here, as is a mesh of more triangles than the documented limit.
void check_face_size(const std::string& path, int line_no, std::string_view line, std::int64_t& triangles) {
  int corners = 0;
  bool in_token = false;
  for (std::size_t i = 1; i < line.size() && line[i] != '#'; ++i) {
    const bool blank = line[i] == ' ' || line[i] == '\t';
    corners += !blank && !in_token;
    in_token = !blank;
  }
  if (corners > 255)
    throw Error(path, line_no, "face with " + std::to_string(corners) + " corners; expected at most 255");
  triangles += std::max(corners - 2, 1);
  if (triangles > limits::max_mesh_triangles)
    throw Error(path, line_no, "more than " + std::to_string(limits::max_mesh_triangles) +
                                   " triangles; expected at most that many (the limit of one mesh, docs/errors.md)");
}

// tinyobjloader reads a face index with atoi-like code that wraps modulo 2^32 and stops at the first non-digit
// ("3abc", "3.7" and "3/abc" read as 3), so every corner of an f line is checked here as strictly as v lines:
// v, v/vt, v//vn or v/vt/vn (OBJ spec, "Vertex/texture-coordinate/normal"), each a non-zero 32-bit integer.
void check_face_tokens(const std::string& path, int line_no, std::string_view line) {
  const auto fail = [&](std::string_view token, const std::string& what) {
    throw Error(path, line_no, "face corner '" + std::string(token) + "': " + what);
  };
  std::size_t p = 1;
  while (p < line.size()) {
    while (p < line.size() && (line[p] == ' ' || line[p] == '\t')) ++p;
    if (p >= line.size()) break;
    std::size_t e = p;
    while (e < line.size() && line[e] != ' ' && line[e] != '\t') ++e;
    const std::string_view token = line.substr(p, e - p);
    p = e;
    if (token[0] == '#') fail(token, "a comment after a face; expected comments on lines of their own");
    if (token == "\\") fail(token, "a line continuation; expected the whole face on one line");
    int parts = 0;
    for (std::size_t b = 0; b <= token.size(); ++parts) {
      const std::size_t slash = std::min(token.find('/', b), token.size());
      const std::string_view part = token.substr(b, slash - b);
      b = slash + 1;
      if (parts >= 3) fail(token, "more than three indices; expected v, v/vt, v//vn or v/vt/vn");
      if (part.empty() && parts == 1 && slash < token.size()) continue;  // v//vn: no texture coordinate
      int value = 0;
      const char* first = part.data() + (!part.empty() && part[0] == '+');
      const auto [end, ec] = std::from_chars(first, part.data() + part.size(), value);
      if (part.empty() || ec != std::errc() || end != part.data() + part.size() || value == 0)
        fail(token, "bad index '" + std::string(part) + "'; expected a non-zero integer within +-2147483647 " +
                        "(v, v/vt, v//vn or v/vt/vn)");
    }
  }
}

// tinyobjloader reads "nan", "inf" and garbage as 0 without a word, so the coordinates of every v and vt line
// are checked here first (std::from_chars: fast, locale-free), and the line of every face is remembered for
// the messages that need it.
// Sizes are checked here too, before tinyobjloader allocates anything for them (core/limits.h).
void check_numbers(const std::string& path, const std::string& text, std::vector<int>& face_lines,
                   std::int64_t& vertices, std::int64_t& triangles) {
  int line_no = 0;
  vertices = triangles = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    ++line_no;
    pos = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const bool is_v = starts_with_tag(line, "v"), is_vt = starts_with_tag(line, "vt");
    if (starts_with_tag(line, "f")) {
      face_lines.push_back(line_no);
      check_face_tokens(path, line_no, line);
      check_face_size(path, line_no, line, triangles);
    }
    if (is_v && ++vertices > limits::max_mesh_vertices)
      throw Error(path, line_no, "more than " + std::to_string(limits::max_mesh_vertices) +
                                     " vertices; expected at most that many (the limit of one mesh, docs/errors.md)");
    if (!is_v && !is_vt) continue;
    const std::size_t want = is_v ? 3 : 2;
    std::size_t got = 0;
    const char* p = line.data() + (is_v ? 1 : 2);
    const char* e = line.data() + line.size();
    while (true) {
      while (p < e && (*p == ' ' || *p == '\t')) ++p;
      if (p >= e || *p == '#') break;
      double value = 0;
      if (*p == '+') ++p;
      auto [next, ec] = std::from_chars(p, e, value);
      const bool separated = next == e || *next == ' ' || *next == '\t';
      if (ec != std::errc() || !separated || !(std::abs(value) <= limits::max_scene_number))
        throw Error(path, line_no,
                    "bad coordinate '" + std::string(p, std::find_if(p, e, [](char c) { return c == ' ' || c == '\t'; })) +
                        "'; expected a finite number of magnitude at most 1e12");
      p = next;
      ++got;
    }
    if (got < want)
      throw Error(path, line_no, std::string("'") + (is_v ? "v" : "vt") + "' line has " + std::to_string(got) +
                                     " numbers; expected at least " + std::to_string(want));
  }
}

int line_in_message(const std::string& msg) {
  std::smatch m;
  static const std::regex re("line ([0-9]+)");
  return std::regex_search(msg, m, re) ? std::stoi(m[1]) : 0;
}

// What tinyobjloader's callbacks fill: the mesh, fanned triangles with the line of their face. Indices are
// resolved as OBJ defines them (1-based; negative counts back from the last v/vt line read so far) and
// range-checked once the whole file is read, as a face may name vertices defined after it.
struct ObjSink {
  const std::string& path;
  const std::vector<int>& face_lines;
  MeshData mesh;
  std::vector<int> tri_face_line;
  std::size_t face_count;
  bool all_uv;

  static Index resolve(int written, std::size_t count) {
    if (written > 0) return Index(written - 1);
    if (written < 0) return Index(std::int64_t(count) + written);
    return -1;  // 0: no such index
  }
  void face(const tinyobj::index_t* idx, int corners) {
    const int line = face_count < face_lines.size() ? face_lines[face_count] : 0;
    ++face_count;
    if (corners < 3) throw Error(path, line, "face with " + std::to_string(corners) + " corners; expected 3 or more");
    if (corners > 3) ++mesh.polygons_triangulated;
    for (int k = 1; k + 1 < corners; ++k) {
      for (const tinyobj::index_t& c : {idx[0], idx[k], idx[k + 1]}) {
        mesh.tri_index.push_back(resolve(c.vertex_index, mesh.positions.size()));
        const Index uv = resolve(c.texcoord_index, mesh.uvs.size());
        all_uv = all_uv && c.texcoord_index != 0;
        mesh.tri_uv.push_back(uv);
      }
      tri_face_line.push_back(line);
    }
  }
};

// The file's text as a read-only stream buffer, without a copy.
class TextView : public std::streambuf {
 public:
  explicit TextView(std::string& text) { setg(text.data(), text.data(), text.data() + text.size()); }
};

std::string first_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  const auto nl = s.find('\n');
  return nl == std::string::npos ? s : s.substr(0, nl);
}

}  // namespace

MeshData read_obj(const std::string& path, MeshCheck check) {
  std::string text = read_text_file(path, "an OBJ mesh");
  std::vector<int> face_lines;
  std::int64_t vertices = 0, triangles = 0;  // counted first, so the mesh's arrays are reserved to size
  check_numbers(path, text, face_lines, vertices, triangles);

  // tinyobjloader's callback reader tokenises the text in place (ObjReader::ParseFromString would copy it into a
  // stringbuf, and build a vector per face and a shape copy of every index): positions, UVs and faces go
  // straight into the mesh. Polygons are split into fans here, to count them and keep each face's line.
  ObjSink sink{path, face_lines, {}, {}, 0, true};
  sink.mesh.source = path;
  sink.mesh.positions.reserve(vertices);
  sink.mesh.tri_index.reserve(3 * std::size_t(triangles));
  sink.mesh.tri_uv.reserve(3 * std::size_t(triangles));
  sink.tri_face_line.reserve(std::size_t(triangles));
  {
    TextView obj_buf(text);
    std::istream obj_in(&obj_buf);
    tinyobj::callback_t cb;
    cb.vertex_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z, tinyobj::real_t) {
      static_cast<ObjSink*>(u)->mesh.positions.push_back(Vec3(x, y, z));
    };
    cb.texcoord_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t) {
      static_cast<ObjSink*>(u)->mesh.uvs.push_back(Vec2(x, y));
    };
    cb.index_cb = [](void* u, tinyobj::index_t* idx, int corners) { static_cast<ObjSink*>(u)->face(idx, corners); };
    std::string warn, err;
    if (!tinyobj::LoadObjWithCallback(obj_in, cb, &sink, nullptr, &warn, &err)) {
      err = first_line(err);
      throw Error(path, line_in_message(err), "malformed OBJ: " + err);
    }
  }
  MeshData& mesh = sink.mesh;
  read_obj_stitches(path, text, mesh);
  std::string().swap(text);  // parsed: free it before the mesh is checked
  const std::size_t nv = mesh.positions.size(), nuv = mesh.uvs.size();
  for (std::size_t k = 0; k < mesh.tri_index.size(); ++k) {
    if (mesh.tri_index[k] < 0 || std::size_t(mesh.tri_index[k]) >= nv)
      throw Error(path, sink.tri_face_line[k / 3],
                  "vertex index out of range; expected 1.." + std::to_string(nv) +
                      " (or negative, counting back from the last v line), indices of existing v lines");
    if (sink.all_uv && (mesh.tri_uv[k] < 0 || std::size_t(mesh.tri_uv[k]) >= nuv))
      throw Error(path, sink.tri_face_line[k / 3],
                  "texture coordinate index out of range; expected 1.." + std::to_string(nuv) +
                      " (or negative, counting back from the last vt line), indices of existing vt lines");
  }
  const bool all_uv = sink.all_uv && nuv > 0;
  const std::vector<int>& tri_face_line = sink.tri_face_line;
  if (mesh.tri_index.empty()) throw Error(path, "no faces; expected 'f' lines of a triangulated surface mesh");
  if (!all_uv) {
    mesh.uvs.clear();
    mesh.tri_uv.clear();
  }

  if (check == MeshCheck::strict) {
    for (Index t = 0; t < mesh.triangle_count(); ++t) {
      const Index* c = &mesh.tri_index[3 * t];
      for (int k = 0; k < 3; ++k) {
        const Index a = c[k], b = c[(k + 1) % 3];
        if (a == b || mesh.positions[a] == mesh.positions[b])
          throw Error(path, tri_face_line[t],
                      "zero-length edge between vertices " + std::to_string(a + 1) + " and " + std::to_string(b + 1) +
                          "; expected distinct vertex positions");
      }
      const Vec3 &p0 = mesh.positions[c[0]], &p1 = mesh.positions[c[1]], &p2 = mesh.positions[c[2]];
      const Real twice_area = (p1 - p0).cross(p2 - p0).norm();
      const Real scale = std::max({(p1 - p0).squaredNorm(), (p2 - p0).squaredNorm(), (p2 - p1).squaredNorm()});
      if (!(twice_area > 1e-12 * scale))
        throw Error(path, tri_face_line[t], "zero-area triangle (collinear corners); expected a proper triangle");
    }
  }
  return std::move(mesh);
}

}  // namespace clothsim::io
