// Tests that run a chapter's program: a shell command, its output and its exit code.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <utility>

namespace rt::testing {

struct ProgramRun {
  int exit_code = -1; // -1 if the program did not exit normally
  std::string output; // stdout and stderr together
};

// Runs `command` through the shell with stderr merged into stdout. Throws std::runtime_error
// if no shell could be started.
ProgramRun run_command(const std::string& command);

// A chapter's program run headless on the CPU backend, so that its tests see the same output on
// every machine: `const HeadlessCpuProgram run_program(RT_CH07_PROGRAM);`, then
// `run_program("--scene room.obj")`.
class HeadlessCpuProgram {
public:
  explicit HeadlessCpuProgram(std::string path) : path_(std::move(path)) {}
  ProgramRun operator()(const std::string& arguments) const;

private:
  std::string path_;
};

// A command line the program must refuse: the exit code it must end with, and a part of the
// one error line it must print.
struct RefusedInput {
  std::string arguments;
  int exit_code;
  const char* says;
};

// Runs `program` on every case and checks its exit code, and that the output is one line that
// contains what the case says.
void check_refused(const HeadlessCpuProgram& program, std::span<const RefusedInput> cases);

// Lines in a program's output (the bad-input tests expect exactly one).
int line_count(const std::string& text);

// A folder of the system's temporary folder for this test process, made if missing:
// <tmp>/<prefix>_<pid>.
std::filesystem::path temp_folder(const std::string& prefix);

} // namespace rt::testing
