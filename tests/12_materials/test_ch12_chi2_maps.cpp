// Chapter 12 tests of ch12_chi2_maps, the chi-square test drawn: on a small grid it writes the
// three panels side by side, finds the right sampler within the noise of its density and the
// wrong twin far outside it, and refuses bad arguments in one line.
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "image_files.h"
#include "run_program.h"

namespace {

using rt::testing::contains;
using rt::testing::ProgramRun;
namespace fs = std::filesystem;

ProgramRun run_maps(const std::string& arguments) {
  return rt::testing::run_command(std::string(RT_CH12_CHI2_PROGRAM) + " " + arguments);
}

// The z of each "chi-square ... z = Z" line, in the order printed.
std::vector<double> z_values(const std::string& output) {
  std::vector<double> z;
  const std::regex line("z = (-?[0-9.]+)");
  for (auto m = std::sregex_iterator(output.begin(), output.end(), line);
       m != std::sregex_iterator(); ++m)
    z.push_back(std::stod((*m)[1].str()));
  return z;
}

} // namespace

TEST_CASE("chi-square maps: three panels, the sampler fits its pdf and the wrong twin does not",
          "[ch12]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch12_chi2");
  for (const char* arguments :
       {"--material rough-glass --roughness 0.5 --theta 40",
        // rough glass, energy compensated, at alpha 0.05, 0.3 and 1
        "--material rough-glass --roughness 0.2236 --theta 60",
        "--material rough-glass --roughness 0.5477 --theta 30",
        "--material rough-glass --roughness 1 --theta 70",
        "--material gold --roughness 0.3 --theta 70", "--material white --theta 20"}) {
    const fs::path image = folder / "maps.png";
    fs::remove(image);
    const ProgramRun run = run_maps(std::string(arguments) +
                                    " --samples 200000 --cells-cos 8 --cells-phi 16 "
                                    "--cell-pixels 2 --output " +
                                    image.string());
    INFO(arguments << "\n" << run.output);
    REQUIRE(run.exit_code == 0);
    // Three panels of 16 x 8 cells of 2 x 2 pixels, 4 pixels apart.
    const rt::Image picture = rt::testing::read_png(image);
    CHECK(picture.width == 3 * 32 + 2 * 4);
    CHECK(picture.height == 16);
    const std::vector<double> z = z_values(run.output);
    REQUIRE(z.size() == 2);
    CHECK(z[0] < 4.0);  // bsdf_sample against bsdf_pdf: within the statistic's noise
    CHECK(z[1] > 20.0); // the twin: far outside it
  }
}

TEST_CASE("chi-square maps: bad arguments are refused in one line", "[ch12]") {
  struct Refused {
    std::string arguments;
    const char* says;
  };
  const Refused cases[] = {
      {"--material unobtainium", "unknown material 'unobtainium'"},
      {"--material glass", "has a smooth lobe"},
      {"--material gold --roughness 0", "has a smooth lobe"},
      {"--theta 90", "--theta"},
      {"--samples 10", "--samples"},
      {"--cells-cos 1", "--cells-cos"},
      {"--output maps.jpg", "a .png file"},
  };
  for (const Refused& c : cases) {
    const ProgramRun run = run_maps(c.arguments);
    INFO(c.arguments << "\n" << run.output);
    CHECK(run.exit_code != 0);
    CHECK(rt::testing::line_count(run.output) == 1);
    CHECK_THAT(run.output, contains(c.says));
  }
}
