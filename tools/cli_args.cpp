#include "tools/cli_args.h"

#include <charconv>

namespace clothsim::cli {

Args parse_args(int argc, char** argv, const std::set<std::string>& with_value, const std::set<std::string>& flags) {
  Args a;
  for (int i = 0; i < argc; ++i) {
    std::string s = argv[i];
    if (s == "--help" || s == "-h") { a.help = true; continue; }
    if (s.rfind("--", 0) != 0 || s.size() == 2) { a.positional.push_back(s); continue; }
    std::string name = s, value;
    const auto eq = s.find('=');
    if (eq != std::string::npos) { name = s.substr(0, eq); value = s.substr(eq + 1); }
    if (with_value.count(name)) {
      if (eq == std::string::npos) {
        if (i + 1 >= argc) throw UsageError("option " + name + " needs a value");
        value = argv[++i];
      }
      a.options[name] = value;
    } else if (flags.count(name) && eq == std::string::npos) {
      a.options[name] = "";
    } else {
      throw UsageError("unknown option '" + s + "'");
    }
  }
  return a;
}

int parse_int(const std::string& option, const std::string& text, int min_value) {
  int v = 0;
  auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || p != text.data() + text.size() || v < min_value)
    throw UsageError("option " + option + " expects an integer >= " + std::to_string(min_value) + ", got '" + text + "'");
  return v;
}

}  // namespace clothsim::cli
