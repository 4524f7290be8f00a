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

// tinyobjloader reads "nan", "inf" and garbage as 0 without a word, so the coordinates of every v and vt line
// are checked here first (std::from_chars: fast, locale-free), and the line of every face is remembered for
// the messages that need it.
// Sizes are checked here too, before tinyobjloader allocates anything for them (core/limits.h).
void check_numbers(const std::string& path, const std::string& text, std::vector<int>& face_lines) {
  int line_no = 0;
  std::int64_t vertices = 0, triangles = 0;
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
      if (ec != std::errc() || !separated || !std::isfinite(value))
        throw Error(path, line_no,
                    "bad coordinate '" + std::string(p, std::find_if(p, e, [](char c) { return c == ' ' || c == '\t'; })) +
                        "'; expected a finite number");
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
  check_numbers(path, text, face_lines);

  // tinyobjloader reads the text in place (ObjReader::ParseFromString would copy it into a stringbuf first);
  // polygons are not triangulated there: we split them ourselves, to count them and keep face lines.
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  {
    TextView obj_buf(text);
    std::istream obj_in(&obj_buf);
    std::stringbuf mtl_buf;
    std::istream mtl_in(&mtl_buf);
    tinyobj::MaterialStreamReader no_materials(mtl_in);
    const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &obj_in, &no_materials,
                                     /*triangulate=*/false, /*default_vcols_fallback=*/false);
    if (!ok) {
      err = first_line(err);
      throw Error(path, line_in_message(err), "malformed OBJ: " + err);
    }
  }
  std::string().swap(text);  // parsed: free it before the mesh is assembled
  if (warn.find("out of bounds") != std::string::npos)
    throw Error(path, line_in_message(warn),
                "face index out of range (" + first_line(warn) + "); expected indices of existing v/vt lines");

  MeshData mesh;
  mesh.source = path;
  const std::size_t nv = attrib.vertices.size() / 3;
  mesh.positions.resize(nv);
  for (std::size_t i = 0; i < nv; ++i)
    mesh.positions[i] = Vec3(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
  const std::size_t nuv = attrib.texcoords.size() / 2;
  mesh.uvs.resize(nuv);
  for (std::size_t i = 0; i < nuv; ++i) mesh.uvs[i] = Vec2(attrib.texcoords[2 * i], attrib.texcoords[2 * i + 1]);

  bool all_uv = nuv > 0;
  std::vector<int> tri_face_line;  // line of the face each triangle came from
  std::size_t triangles = 0;       // reserved up front: growing by doubling would hold the arrays twice
  for (const tinyobj::shape_t& shape : shapes)
    for (const unsigned char corners : shape.mesh.num_face_vertices) triangles += corners > 2 ? corners - 2 : 0;
  mesh.tri_index.reserve(3 * triangles);
  mesh.tri_uv.reserve(3 * triangles);
  tri_face_line.reserve(triangles);
  std::size_t face = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (const unsigned char corners : shape.mesh.num_face_vertices) {
      const tinyobj::index_t* idx = &shape.mesh.indices[offset];
      const int line = face < face_lines.size() ? face_lines[face] : 0;
      if (corners < 3) throw Error(path, line, "face with " + std::to_string(corners) + " corners; expected 3 or more");
      if (corners > 3) ++mesh.polygons_triangulated;
      for (unsigned k = 1; k + 1 < corners; ++k) {
        for (const tinyobj::index_t& c : {idx[0], idx[k], idx[k + 1]}) {
          if (c.vertex_index < 0 || std::size_t(c.vertex_index) >= nv)
            throw Error(path, line, "vertex index out of range; expected 1.." + std::to_string(nv));
          mesh.tri_index.push_back(c.vertex_index);
          if (c.texcoord_index < 0) all_uv = false;
          mesh.tri_uv.push_back(c.texcoord_index);
        }
        tri_face_line.push_back(line);
      }
      offset += corners;
      ++face;
    }
  }
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
  return mesh;
}

}  // namespace clothsim::io
