// Chapter 11: what every progressive renderer's program does alike. See progressive_program.h.
#include "progressive_program.h"

#include <string>

#include "rt/error.h"
#include "rt/program_output.h"

namespace rt::ch11 {

void add_sampler_options(CLI::App& app, RenderSettings& settings, bool& compare_samplers) {
  app.add_option_function<std::string>(
         "--sampler", [&](const std::string& t) { settings.sampler = parse_sampler(t); },
         "Where the paths' numbers come from: independent, stratified, sobol or zsobol (the "
         "image and the window)")
      ->default_str(to_string(settings.sampler));
  app.add_flag("--samplers", compare_samplers,
               "With --convergence: every sampler's error against run time, not the "
               "strategies'");
}

void refuse_progressive_flags(const CLI::App& app, const ch03::ProgramOptions& options,
                              bool convergence) {
  const auto given = [&](const char* flag) { return app.count(flag) > 0; };
  if (convergence)
    for (const char* flag : {"--window", "--variant", "--strategy", "--sampler", "--output",
                             "--seconds", "--image-only", "--exposure", "--frames"})
      if (given(flag))
        throw UsageError(std::string("--convergence measures every variant and strategy "
                                     "(with --samplers, every sampler) against a reference "
                                     "and writes no image: not with ") +
                         flag);
  if (!convergence && given("--reference-spp"))
    throw UsageError("--reference-spp goes with --convergence");
  if (!convergence && given("--samplers"))
    throw UsageError("--samplers goes with --convergence");
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

void add_window_frame(ProgressiveRenderer& renderer, ShownView& shown, const CameraSpec& camera,
                      Extent extent, const RenderSettings& settings, float exposure,
                      Rgba8* pixels) {
  const bool same = shown && shown->second.width == extent.width &&
                    shown->second.height == extent.height && shown->first.eye == camera.eye &&
                    shown->first.target == camera.target && shown->first.up == camera.up &&
                    shown->first.fov_degrees == camera.fov_degrees;
  if (!same) renderer.restart(camera, extent);
  shown = {camera, extent};
  renderer.add_samples(settings, 1);
  renderer.tone_map_into(pixels, exposure);
}

} // namespace rt::ch11
