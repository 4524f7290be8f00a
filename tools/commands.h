#pragma once
// One function per clothsim command; each returns the process exit code (0 ok, 2 bad input, 3 diverged).
namespace clothsim::cli {

int cmd_run(int argc, char** argv);
int cmd_validate(int argc, char** argv);
int cmd_info(int argc, char** argv);
int cmd_batch(int argc, char** argv);
int cmd_study(int argc, char** argv);

// Exit codes shared by every command.
inline constexpr int exit_ok = 0;
inline constexpr int exit_bad_input = 2;
inline constexpr int exit_diverged = 3;

}  // namespace clothsim::cli
