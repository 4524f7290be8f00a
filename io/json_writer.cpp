#include "io/json_writer.h"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace clothsim::io {

JsonWriter& JsonWriter::value(double v) {
  comma();
  if (!std::isfinite(v)) { s_ += "null"; return *this; }
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  s_.append(buf, r.ptr);
  return *this;
}

void JsonWriter::string_literal(std::string_view v) {
  s_ += '"';
  for (char c : v) {
    if (c == '"' || c == '\\') { s_ += '\\'; s_ += c; }
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      s_ += buf;
    } else s_ += c;
  }
  s_ += '"';
}

}  // namespace clothsim::io
