#pragma once
// Command-line parsing for the clothsim commands: positional arguments plus --options, where an unknown option
// is an error (exit code 2), as is a missing value.
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace clothsim::cli {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;  // flags map to ""
  bool help = false;
  bool has(const std::string& k) const { return options.count(k) > 0; }
  std::string get(const std::string& k, const std::string& fallback = "") const {
    auto it = options.find(k);
    return it == options.end() ? fallback : it->second;
  }
};

// `with_value`: options taking a value (--out DIR or --out=DIR); `flags`: options without one.
Args parse_args(int argc, char** argv, const std::set<std::string>& with_value, const std::set<std::string>& flags);
int parse_int(const std::string& option, const std::string& text, int min_value);

}  // namespace clothsim::cli
