#pragma once
// The `clothsim study` subcommands. Each measures one trade-off on reference problems built in memory and
// writes CSV and gnuplot charts into --out; each returns the process exit code.
namespace clothsim::cli {

int study_accuracy(int argc, char** argv);   // tools/study_accuracy.cpp
int study_stability(int argc, char** argv);  // tools/study_stability.cpp

}  // namespace clothsim::cli
