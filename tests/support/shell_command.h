#pragma once
// Runs a shell command line (for tests that need a shell around clothsim: ulimit, mpirun) and collects its
// stdout and stderr together.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace clothsim::test {

struct ShellResult {
  int status = -1;     // as from waitpid
  std::string output;  // stdout and stderr together
};

inline ShellResult run_shell(const std::string& command) {
  ShellResult r;
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  r.status = pclose(p);
  return r;
}

}  // namespace clothsim::test
