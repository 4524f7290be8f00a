// clothsim study <name> ...: dispatches to one study (tools/studies.h).
#include <cstdio>
#include <cstring>
#include <string>

#include "tools/cli_args.h"
#include "tools/commands.h"
#include "tools/studies.h"

namespace clothsim::cli {

int cmd_study(int argc, char** argv) {
  const char* help =
      "usage: clothsim study <name> [options]\n"
      "studies:\n"
      "  accuracy [--out DIR] [--quick]             error against CPU time and time step, every integrator\n"
      "  stability [--out DIR] [--quick]            largest stable time step and stiffness against theory\n"
      "  scaling SCENE.xml --threads 1,2,4 [--weak]  speed-up and efficiency against threads\n"
      "  autostep [SCENE.xml ...] [--family N]       timestep=\"auto\" against the largest stable step\n"
      "Run 'clothsim study <name> --help' for the options of a study. The accuracy and stability charts need\n"
      "gnuplot (tools/setup installs it); without it their CSV files are still written.";
  if (argc < 1 || !std::strcmp(argv[0], "--help") || !std::strcmp(argv[0], "-h")) {
    std::puts(help);
    return argc < 1 ? exit_bad_input : exit_ok;
  }
  const std::string name = argv[0];
  if (name == "accuracy") return study_accuracy(argc - 1, argv + 1);
  if (name == "stability") return study_stability(argc - 1, argv + 1);
  if (name == "scaling") return study_scaling(argc - 1, argv + 1);
  if (name == "autostep") return study_auto_step(argc - 1, argv + 1);
  throw UsageError("unknown study '" + name + "'; expected one of: accuracy, stability, scaling, autostep");
}

}  // namespace clothsim::cli
