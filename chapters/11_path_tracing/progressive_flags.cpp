// Chapter 11: the flags every progressive renderer's program refuses. See progressive_flags.h.
#include "progressive_flags.h"

#include <string>

#include "rt/error.h"
#include "rt/program_output.h"

namespace rt::ch11 {

void refuse_progressive_flags(const CLI::App& app, const ch03::ProgramOptions& options,
                              bool convergence) {
  const auto given = [&](const char* flag) { return app.count(flag) > 0; };
  if (convergence)
    for (const char* flag : {"--window", "--variant", "--strategy", "--output", "--seconds",
                             "--image-only", "--exposure", "--frames"})
      if (given(flag))
        throw UsageError(std::string("--convergence measures every variant and strategy "
                                     "against a reference and writes no image: not with ") +
                         flag);
  if (!convergence && given("--reference-spp"))
    throw UsageError("--reference-spp goes with --convergence");
  if (given("--spp") && given("--seconds"))
    throw UsageError("--spp and --seconds both say how long to render: give one");
  const std::string& output = options.common.output;
  if (given("--exposure") && !options.display.window &&
      (output.empty() || is_linear_image_path(output)))
    throw UsageError("--exposure scales the tone-mapped picture (a .png or the window); " +
                     (output.empty() ? std::string("there is no --output")
                                     : output + " holds the radiance itself"));
  if (given("--output") && output.empty() && options.common.json.empty() &&
      (options.display.headless || options.image_only))
    throw UsageError("--output \"\" and no --json: the run would write nothing (leave out "
                     "--output for the image, or give --json for the report)");
}

} // namespace rt::ch11
