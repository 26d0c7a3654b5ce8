// See run_program.h.
#include "run_program.h"

#include "rt_catch.h"

#include <cstdio>
#include <stdexcept>

#include <sys/wait.h>
#include <unistd.h>

namespace rt::testing {

ProgramRun run_command(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("cannot start: " + command);
  ProgramRun run;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) run.output += buffer;
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

ProgramRun HeadlessCpuProgram::operator()(const std::string& arguments) const {
  return run_command(path_ + " --headless --backend cpu " + arguments);
}

void check_refused(const HeadlessCpuProgram& program, std::span<const RefusedInput> cases) {
  for (const RefusedInput& c : cases) {
    CAPTURE(c.arguments);
    const ProgramRun run = program(c.arguments);
    INFO(run.output);
    CHECK(run.exit_code == c.exit_code);
    CHECK(line_count(run.output) == 1);
    CHECK_THAT(run.output, contains(c.says));
  }
}

int line_count(const std::string& text) {
  int lines = 0;
  for (const char c : text) lines += c == '\n';
  return lines;
}

std::filesystem::path temp_folder(const std::string& prefix) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  return folder;
}

} // namespace rt::testing
