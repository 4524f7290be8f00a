#pragma once
// The `clothsim study` sub-commands, one file each (tools/study_<name>.cpp); each returns the exit code.
namespace clothsim::cli {

// study scaling SCENE.xml --threads 1,2,4 [--weak]: speed-up and parallel efficiency (issue 7 §4).
int study_scaling(int argc, char** argv);

}  // namespace clothsim::cli
