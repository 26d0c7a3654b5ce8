// Tests that run a chapter's program: a shell command, its output and its exit code.
#pragma once

#include <string>

namespace rt::testing {

struct ProgramRun {
  int exit_code = -1; // -1 if the program did not exit normally
  std::string output; // stdout and stderr together
};

// Runs `command` through the shell with stderr merged into stdout. Throws std::runtime_error
// if no shell could be started.
ProgramRun run_command(const std::string& command);

} // namespace rt::testing
