// Chapter 03: the program skeleton. See program.h.
#include "program.h"

#include <iostream>

#include "camera_cli.h"
#include "rt/backend_image.h"
#include "rt/error.h"
#include "rt/output_file.h"
#include "rt/program_output.h"

namespace rt::ch03 {

namespace {

// The frames the window draws and a headless run writes: render, or render_with_radiance
// without the linear values.
FrameRenderer frame_renderer(const ProgramParts& parts) {
  if (parts.render) return parts.render;
  return [&parts](Backend backend, const CameraSpec& camera, Extent extent, Rgba8* pixels) {
    parts.render_with_radiance(backend, camera, extent, pixels, nullptr);
  };
}

// The window's --output is a screenshot of what it showed: a picture, never linear values.
// Refused before the window runs: at once for --window, once it opened for a window by default.
void refuse_linear_screenshot(const ProgramOptions& options, bool window_open) {
  if ((window_open || options.display.window) && options.common.frames > 0 &&
      is_linear_image_path(options.common.output))
    throw UsageError("the window's --output is a screenshot, a picture: give it a .png (the "
                     "linear values come from a --headless run)");
}

} // namespace

void add_program_options(CLI::App& app, ProgramOptions& options) {
  add_common_options(app, options.common);
  add_camera_options(app, options.camera);
}

void add_image_only_option(CLI::App& app, ProgramOptions& options) {
  app.add_flag("--image-only", options.image_only,
               "Headless: write the --output image and skip the measurements");
}

int run_program_main(CLI::App& app, int argc, char** argv, ProgramOptions& options,
                     const std::function<int()>& body) {
  add_display_options(app, options.display);
  return run_main(app, argc, argv, options.common, [&] {
    const auto given = [&](const char* flag) { return app.get_option(flag)->count() > 0; };
    options.eye_given = given("--eye");
    options.target_given = given("--target");
    options.fov_given = given("--fov");
    options.width_given = given("--width");
    options.height_given = given("--height");
    // --image-only measures nothing, so there would be no report to write.
    refuse_linear_screenshot(options, false);
    if (options.image_only && !options.common.json.empty())
      throw UsageError("--json writes the report, and --image-only makes none: give one");
    return body();
  });
}

int run_window_or_headless(const ProgramOptions& options, Backend backend,
                           const ProgramParts& parts, Report& report) {
  if (!show_in_window(options, backend, parts, report)) {
    if (options.image_only) {
      write_image_only(options, backend, parts);
      return 0;
    }
    report.add_context("mode", k_headless_mode);
    parts.measure(report);
    if (!options.common.output.empty()) write_program_image(options, backend, parts);
  }
  finish_report(report, options.common);
  return 0;
}

bool show_in_window(const ProgramOptions& options, Backend backend, const ProgramParts& parts,
                    Report& report) {
  const std::string title = parts.chapter + ": " + parts.window_title;
  const std::unique_ptr<ch02::Viewer> viewer =
      open_viewer(options.display, options.common.extent(), title);
  if (!viewer) return false;
  refuse_linear_screenshot(options, true);
  report.add_context("mode", k_window_mode);
  for (const auto& [key, value] : parts.window_context) report.add_context(key, value);
  const WindowSettings settings{title, options.common.frames, parts.chapter + "_screenshot"};
  const WindowResult shown =
      run_window(*viewer, backend, parts.camera, settings, frame_renderer(parts));
  if (shown.frames == 0) return true;
  report.add_row(parts.window_row(shown));
  if (options.common.frames > 0 && !options.common.output.empty())
    write_output_image(options.common.output, shown.last_screen, "screenshot");
  return true;
}

void write_image_only(const ProgramOptions& options, Backend backend,
                      const ProgramParts& parts) {
  if (options.common.output.empty()) throw UsageError("--image-only needs --output");
  write_program_image(options, backend, parts);
}

void write_program_image(const ProgramOptions& options, Backend backend,
                         const ProgramParts& parts) {
  const std::string& path = options.common.output;
  const Extent extent = options.common.extent();
  if ((parts.linear_image || parts.render_with_radiance) && is_linear_image_path(path)) {
    write_linear_image(
        path,
        parts.linear_image
            ? parts.linear_image()
            : render_into_linear_image(backend, extent, [&](Rgba8* pixels, Vec3f* radiance) {
                parts.render_with_radiance(backend, parts.camera, extent, pixels, radiance);
              }));
    std::cout << "wrote " << path << " (linear values"
              << (parts.image_note.empty() ? "" : ", " + parts.image_note) << ")\n";
    return;
  }
  const Image image =
      parts.image ? parts.image() : render_into_image(backend, extent, [&](Rgba8* pixels) {
        frame_renderer(parts)(backend, parts.camera, extent, pixels);
      });
  write_output_image(options.common.output, image, parts.image_note);
}

ReportRow window_row(const std::string& variant, Backend backend, const WindowResult& shown) {
  return {variant + ", window (" + shown.path + ")",
          to_string(backend),
          shown.frame_time.median_ms,
          shown.extent().pixel_count() / (shown.frame_time.median_ms * 1e3),
          "",
          {}};
}

ReportRow window_fps_row(const std::string& variant, Backend backend,
                         const WindowResult& shown) {
  ReportRow row = window_row(variant, backend, shown);
  row.error = format_fixed(1000.0 / shown.frame_time.median_ms, 1) + " frames/s on screen";
  row.metrics = {{"fps", 1000.0 / shown.frame_time.median_ms}};
  return row;
}

ReportRow window_row(const std::string& variant, Backend backend, const WindowResult& shown,
                     std::size_t pixels_differing) {
  ReportRow row = window_row(variant, backend, shown);
  row.error = group_digits(static_cast<long long>(pixels_differing)) + " px differ on screen";
  row.metrics = {{"pixels_differing", double(pixels_differing)}};
  return row;
}

} // namespace rt::ch03
