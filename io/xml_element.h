#pragma once
// Typed attributes of one element of the scene file, each problem reported with the file and the element's line
// (docs/errors.md): the reader io/scene_xml.cpp builds on.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <pugixml.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/limits.h"
#include "core/math.h"

namespace clothsim::io {

// Reads typed attributes of one element and reports every problem with the file and the element's line.
class ElementReader {
 public:
  ElementReader(const std::string& file, const std::string& text, pugi::xml_node node,
                std::initializer_list<const char*> allowed)
      : file_(file), node_(node), line_(line_of(text, node.offset_debug())) {
    const std::set<std::string> ok(allowed.begin(), allowed.end());
    std::set<std::string> seen;
    for (pugi::xml_attribute a : node.attributes()) {
      if (!ok.count(a.name()))
        fail("unknown attribute '" + std::string(a.name()) + "'; " +
             (allowed.size() ? "expected one of: " + join(allowed) : std::string("expected no attributes")));
      // pugixml keeps both copies of a repeated attribute and node.attribute() finds the first.
      if (!seen.insert(a.name()).second) fail("attribute '" + std::string(a.name()) + "' appears twice; expected it once");
    }
  }

  // An element that should not be there at all: reported before (and instead of) its attributes.
  [[noreturn]] static void unknown_element(const std::string& file, const std::string& text, pugi::xml_node node,
                                           const std::string& what) {
    throw Error(file, line_of(text, node.offset_debug()), "<" + std::string(node.name()) + ">: " + what);
  }

  static int line_of(const std::string& text, std::ptrdiff_t offset) {
    if (offset < 0) return 0;
    return 1 + int(std::count(text.begin(), text.begin() + std::min<std::size_t>(offset, text.size()), '\n'));
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(file_, line_, "<" + std::string(node_.name()) + ">: " + what);
  }
  int line() const { return line_; }
  bool has(const char* name) const { return bool(node_.attribute(name)); }

  std::string text(const char* name, std::string fallback = "") const {
    pugi::xml_attribute a = node_.attribute(name);
    return a ? std::string(a.value()) : fallback;
  }

  // A name or path that ends up inside an output file (an OBJ's 'o' line, a .mtl): a control character such as
  // a newline (&#10;) would start a line of its own there.
  std::string name_text(const char* name, std::string fallback = "") const {
    std::string v = text(name, std::move(fallback));
    const auto c = std::find_if(v.begin(), v.end(), [](char ch) { return (unsigned char)ch < 0x20 || ch == 0x7f; });
    if (c != v.end())  // the value itself is not echoed: its newline would split the message
      fail("attribute " + std::string(name) + " holds control character " + std::to_string(int(*c)) + " at position " +
           std::to_string(c - v.begin() + 1) + "; expected a name without control characters (newline, tab, ...)");
    return v;
  }

  Real number(const char* name, Real fallback, const char* expected = "a number") const {
    pugi::xml_attribute a = node_.attribute(name);
    if (!a) return fallback;
    return parse_numbers(name, a.value(), 1, expected)[0];
  }

  Real positive(const char* name, Real fallback, const char* unit) const {
    const std::string expected = std::string("a positive number (") + unit + ")";
    const Real v = number(name, fallback, expected.c_str());
    if (!(v > 0)) bad(name, expected);
    return v;
  }

  Real non_negative(const char* name, Real fallback, const char* unit) const {
    const std::string expected = std::string("a number >= 0 (") + unit + ")";
    const Real v = number(name, fallback, expected.c_str());
    if (!(v >= 0)) bad(name, expected);
    return v;
  }

  int integer(const char* name, int fallback) const {
    pugi::xml_attribute a = node_.attribute(name);
    if (!a) return fallback;
    const std::string s = trim(a.value());
    int v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || p != s.data() + s.size()) bad(name, "an integer");
    return v;
  }

  Vec3 vec3(const char* name, const Vec3& fallback) const {
    pugi::xml_attribute a = node_.attribute(name);
    if (!a) return fallback;
    const auto v = parse_numbers(name, a.value(), 3, "three numbers \"x y z\"");
    return Vec3(v[0], v[1], v[2]);
  }

  bool boolean(const char* name, bool fallback) const {
    pugi::xml_attribute a = node_.attribute(name);
    if (!a) return fallback;
    const std::string s = trim(a.value());
    if (s == "true" || s == "1") return true;
    if (s == "false" || s == "0") return false;
    bad(name, "true or false");
  }

  std::vector<Real> numbers(const char* name, std::size_t count, const char* expected) const {
    return parse_numbers(name, node_.attribute(name).value(), count, expected);
  }

  [[noreturn]] void bad(const char* name, const std::string& expected) const {
    fail("attribute " + std::string(name) + "=\"" + node_.attribute(name).value() + "\"; expected " + expected);
  }

 private:
  static std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
  }
  static std::string join(std::initializer_list<const char*> names) {
    std::string s;
    for (const char* n : names) s += (s.empty() ? "" : ", ") + std::string(n);
    return s;
  }
  // `count` numbers separated by blanks (count 0: any number of them).
  std::vector<Real> parse_numbers(const char* name, const char* value, std::size_t count, const char* expected) const {
    std::vector<Real> out;
    std::istringstream in(value);
    std::string tok;
    while (in >> tok) {
      double v = 0;
      const char* b = tok.data() + (tok[0] == '+' ? 1 : 0);
      auto [p, ec] = std::from_chars(b, tok.data() + tok.size(), v);
      if (ec != std::errc() || p != tok.data() + tok.size() || !std::isfinite(v)) bad(name, expected);
      if (std::abs(v) > limits::max_scene_number) bad(name, std::string(expected) + ", of magnitude at most 1e12");
      out.push_back(v);
    }
    if ((count > 0 && out.size() != count) || out.empty()) bad(name, expected);
    return out;
  }

  const std::string& file_;
  pugi::xml_node node_;
  int line_;
};

}  // namespace clothsim::io
