// Tests that run a chapter's program: a shell command, its output and its exit code.
#pragma once

#include <filesystem>
#include <string>

namespace rt::testing {

struct ProgramRun {
  int exit_code = -1; // -1 if the program did not exit normally
  std::string output; // stdout and stderr together
};

// Runs `command` through the shell with stderr merged into stdout. Throws std::runtime_error
// if no shell could be started.
ProgramRun run_command(const std::string& command);

// Lines in a program's output (the bad-input tests expect exactly one).
int line_count(const std::string& text);

// A folder of the system's temporary folder for this test process, made if missing:
// <tmp>/<prefix>_<pid>.
std::filesystem::path temp_folder(const std::string& prefix);

} // namespace rt::testing
