#include "io/obj_stitches.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include "core/error.h"

namespace clothsim::io {
namespace {

// The next blank-separated token of line from pos ("" at the end or at a comment).
std::string_view next_token(std::string_view line, std::size_t& pos) {
  while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t')) ++pos;
  if (pos >= line.size() || line[pos] == '#') return {};
  const std::size_t begin = pos;
  while (pos < line.size() && line[pos] != ' ' && line[pos] != '\t') ++pos;
  return line.substr(begin, pos - begin);
}

template <class T>
bool parse_number(std::string_view token, T& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

void read_stitch(const std::string& path, int line_no, std::string_view line, MeshData& mesh) {
  std::size_t pos = 6;  // after "stitch"
  long long idx[3];
  const Index n = mesh.vertex_count();
  for (long long& v : idx) {
    const std::string_view t = next_token(line, pos);
    if (!parse_number(t, v))
      throw Error(path, line_no, "bad stitch index '" + std::string(t) + "'; expected 'stitch i j k w' with 0-based vertex indices");
    if (v < 0 || v >= n)
      throw Error(path, line_no, "stitch vertex " + std::to_string(v) + " is out of range; expected 0.." +
                                     std::to_string(n - 1) + " (0-based)");
  }
  const std::string_view t = next_token(line, pos);
  double w = 0;
  if (!parse_number(t, w) || !std::isfinite(w))
    throw Error(path, line_no, "bad stitch weight '" + std::string(t) + "'; expected a number in [0, 1]");
  if (w < 0 || w > 1)
    throw Error(path, line_no, "stitch weight " + std::string(t) + " is outside [0, 1]; expected 0 <= w <= 1");
  if (!next_token(line, pos).empty())
    throw Error(path, line_no, "stitch record has more than 4 values; expected 'stitch i j k w'");
  if (idx[0] == idx[1] || idx[0] == idx[2])
    throw Error(path, line_no, "stitch sews vertex " + std::to_string(idx[0]) + " to itself; expected distinct vertices");
  mesh.stitch_a.push_back(Index(idx[0]));
  mesh.stitch_b.push_back(Index(idx[1]));
  mesh.stitch_c.push_back(Index(idx[2]));
  mesh.stitch_w.push_back(w);
}

bool has_tag(std::string_view line, std::string_view tag) {
  return line.size() > tag.size() && line.substr(0, tag.size()) == tag &&
         (line[tag.size()] == ' ' || line[tag.size()] == '\t');
}

}  // namespace

void read_obj_stitches(const std::string& path, const std::string& text, MeshData& mesh) {
  // Jumps from one "stitch" or "seam" to the next (most meshes have none), counting lines only up to each.
  int line_no = 1;
  std::size_t counted = 0;
  for (std::size_t at = text.find("s"); at != std::string::npos; at = text.find("s", at + 1)) {
    if (at > 0 && text[at - 1] != '\n') continue;
    const std::size_t end = std::min(text.find('\n', at), text.size());
    std::string_view line(text.data() + at, end - at);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const bool stitch = has_tag(line, "stitch"), seam = has_tag(line, "seam");
    if (!stitch && !seam) continue;
    line_no += int(std::count(text.begin() + counted, text.begin() + at, '\n'));
    counted = at;
    if (stitch) read_stitch(path, line_no, line, mesh);
    else ++mesh.seam_count;
  }
}

}  // namespace clothsim::io
