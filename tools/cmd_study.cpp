// clothsim study <name>: dispatches to the studies of tools/studies.h.
#include <cstdio>
#include <string>

#include "tools/cli_args.h"
#include "tools/commands.h"
#include "tools/studies.h"

namespace clothsim::cli {
namespace {

const char* study_help =
    "usage: clothsim study <name> [--out DIR] [--quick]\n"
    "  accuracy   error against CPU time and time step for every integrator (docs/accuracy.md)\n"
    "  stability  largest stable time step and stiffness of every integrator, against theory\n"
    "  --out DIR  where the CSV files and the PNG/SVG charts go (default: study-<name>)\n"
    "  --quick    smaller problems and looser tolerances: seconds instead of minutes, for the tests\n"
    "Charts need gnuplot (tools/setup installs it); without it the CSV files are still written.";

}  // namespace

int cmd_study(int argc, char** argv) {
  if (argc < 1 || std::string(argv[0]) == "--help" || std::string(argv[0]) == "-h") {
    std::puts(study_help);
    return argc < 1 ? exit_bad_input : exit_ok;
  }
  const std::string name = argv[0];
  if (name == "accuracy") return study_accuracy(argc - 1, argv + 1);
  if (name == "stability") return study_stability(argc - 1, argv + 1);
  throw UsageError("unknown study '" + name + "'; expected accuracy or stability");
}

}  // namespace clothsim::cli
