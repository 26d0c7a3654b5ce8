// Chapter 02 tests of an unreachable display: the error names the display the environment
// gave, and the program's one error line is all the reader sees (the display libraries' own
// complaints, such as "XDG_RUNTIME_DIR is invalid", stay out of a run).
#include <cstdlib>
#include <string>

#include "rt_catch.h"

#include "run_program.h"

#include "viewer.h"

using namespace rt;
using namespace rt::ch02;
using rt::testing::contains;
using rt::testing::line_count;

namespace {

// The program in an environment that names only the given displays.
rt::testing::ProgramRun run_with(const std::string& environment, const std::string& arguments) {
  return rt::testing::run_command("env -u DISPLAY -u WAYLAND_DISPLAY -u XDG_RUNTIME_DIR " +
                                  environment + " " + RT_CH02_PROGRAM + " --backend cpu " +
                                  arguments);
}

} // namespace

TEST_CASE("a display that cannot be reached is named in the error", "[ch02]") {
  const char* display = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  const std::string saved_display = display ? display : "";
  const std::string saved_wayland = wayland ? wayland : "";
  unsetenv("WAYLAND_DISPLAY");
  setenv("DISPLAY", ":987654", 1);
  std::string message = "no error";
  try {
    const Viewer viewer(Extent{64, 32}, "test", false);
  } catch (const DisplayError& e) {
    message = e.what();
  }
  CHECK_THAT(message, contains("cannot open the X display ':987654' (DISPLAY)"));
  if (display)
    setenv("DISPLAY", saved_display.c_str(), 1);
  else
    unsetenv("DISPLAY");
  if (wayland) setenv("WAYLAND_DISPLAY", saved_wayland.c_str(), 1);
}

TEST_CASE("program: an unreachable display is one line that names it", "[ch02]") {
  const rt::testing::ProgramRun x11 = run_with("DISPLAY=:99", "--window");
  INFO(x11.output);
  CHECK(x11.exit_code == 1);
  CHECK(line_count(x11.output) == 1);
  CHECK_THAT(x11.output, contains("':99' (DISPLAY)"));
  // Both kinds named, neither there: SDL probes both, and what the libraries print comes
  // inside the one line, not before it.
  const rt::testing::ProgramRun both =
      run_with("DISPLAY=:99 WAYLAND_DISPLAY=nowhere-9", "--window");
  INFO(both.output);
  CHECK(both.exit_code == 1);
  CHECK(line_count(both.output) == 1);
  CHECK_THAT(both.output, contains("':99' (DISPLAY) or the Wayland display 'nowhere-9'"));
  // Without --window the program goes headless with a notice, and nothing else is printed
  // before it.
  const std::string image = (rt::testing::temp_folder("rt_ch02") / "frame.png").string();
  const rt::testing::ProgramRun headless =
      run_with("DISPLAY=:99", "--frames 1 --width 16 --height 8 --output " + image);
  INFO(headless.output);
  CHECK(headless.exit_code == 0);
  CHECK_THAT(headless.output,
             rt::testing::starts_with("notice: cannot open the X display ':99' (DISPLAY)"));
}
