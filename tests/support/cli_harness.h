#pragma once
// Runs the real clothsim binary on scenes written into a scratch folder, for the CLI and scenario tests.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

namespace clothsim::test {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// `env`: a prefix for the shell command, e.g. "env -u OPENBLAS_CORETYPE " (with its trailing space).
inline CliResult run_cli(const std::string& args, const std::string& env = {}) {
  CliResult r;
  const std::string cmd = env + std::string(CLOTHSIM_BIN) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// A fresh scratch folder under the build tree's temp dir, removed and recreated for each test.
inline std::filesystem::path scratch_dir(const std::string& name) {
  // One tree per test process: several checkouts (or ctest -j) on one machine must not share folders.
  const auto dir = std::filesystem::temp_directory_path() / ("clothsim_tests." + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Names of the regular files in a folder, sorted.
inline std::vector<std::string> files_in(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  if (std::filesystem::exists(dir))
    for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace clothsim::test
