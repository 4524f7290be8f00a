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
      "  scaling SCENE.xml --threads 1,2,4 [--weak]  speed-up and efficiency against threads\n"
      "Run 'clothsim study <name> --help' for the options of a study.";
  if (argc < 1 || !std::strcmp(argv[0], "--help") || !std::strcmp(argv[0], "-h")) {
    std::puts(help);
    return argc < 1 ? exit_bad_input : exit_ok;
  }
  const std::string name = argv[0];
  if (name == "scaling") return study_scaling(argc - 1, argv + 1);
  throw UsageError("unknown study '" + name + "'; expected one of: scaling");
}

}  // namespace clothsim::cli
