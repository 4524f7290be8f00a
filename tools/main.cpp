// clothsim: the command-line front end. Errors from input are caught here, once, and become exit code 2.
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "core/blas_kernel.h"
#include "core/error.h"
#include "tools/cli_args.h"
#include "tools/commands.h"

namespace {

const char* usage =
    "usage: clothsim <command> [options]\n"
    "commands:\n"
    "  run SCENE.xml       simulate and write one OBJ per frame\n"
    "  validate SCENE.xml  check a scene without simulating\n"
    "  info MESH.obj       mesh and spring counts, topology checks\n"
    "  batch LIST          run many scenes, N at a time, resumable\n"
    "  study NAME ...      studies: accuracy, stability (integrators), scaling (threads)\n"
    "Run 'clothsim <command> --help' for the options of a command.\n";

// OpenBLAS picks its kernels once, when it is loaded, from the CPU's model number; on a CPU newer than it knows it
// runs its generic Prescott (SSE3) kernels, and the Cholesky factorisation runs at about two thirds of its speed
// (docs/performance.md, "The BLAS kernels"). Where the user set no OPENBLAS_CORETYPE, clothsim sets the one the
// CPU's vector units allow and starts itself again, so that OpenBLAS loads with it. Returns when there is nothing
// to change or the restart failed; the run then goes on with the kernels loaded, and says so.
void restart_with_better_blas_kernels(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE")) return;  // the user's choice, or this restart's own
  // Valgrind's CPU has neither the model nor the units, and a restart would leave valgrind.
  const char* preload = std::getenv("LD_PRELOAD");
  if (preload && std::strstr(preload, "vgpreload")) return;
  const std::string coretype =
      clothsim::better_openblas_coretype(clothsim::blas_kernel_name(), clothsim::cpu_vector_units());
  if (coretype.empty()) return;
  setenv("OPENBLAS_CORETYPE", coretype.c_str(), 1);
  setenv("CLOTHSIM_CHOSE_OPENBLAS_CORETYPE", "1", 1);
  execv("/proc/self/exe", argv);
  unsetenv("OPENBLAS_CORETYPE");
  unsetenv("CLOTHSIM_CHOSE_OPENBLAS_CORETYPE");
}

}  // namespace

int main(int argc, char** argv) {
  using namespace clothsim::cli;
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    std::fputs(usage, argc < 2 ? stderr : stdout);
    return argc < 2 ? exit_bad_input : exit_ok;
  }
  // A file-size limit (ulimit -f) must surface as a failed write (EFBIG, exit code 2), not kill the process.
  std::signal(SIGXFSZ, SIG_IGN);
  const std::string command = argv[1];
  if (command == "run" || command == "batch" || command == "study") restart_with_better_blas_kernels(argv);
  try {
    if (command == "run") return cmd_run(argc - 2, argv + 2);
    if (command == "validate") return cmd_validate(argc - 2, argv + 2);
    if (command == "info") return cmd_info(argc - 2, argv + 2);
    if (command == "batch") return cmd_batch(argc - 2, argv + 2);
    if (command == "study") return cmd_study(argc - 2, argv + 2);
    std::fprintf(stderr, "clothsim: unknown command '%s'\n%s", command.c_str(), usage);
    return exit_bad_input;
  } catch (const clothsim::Error& e) {
    std::fprintf(stderr, "clothsim: error: %s\n", e.what());
    return exit_bad_input;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "clothsim %s: %s (see 'clothsim %s --help')\n", command.c_str(), e.what(), command.c_str());
    return exit_bad_input;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "clothsim: error: out of memory\n");
    return exit_bad_input;
  }
}
