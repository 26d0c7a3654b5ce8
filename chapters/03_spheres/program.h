// Chapter 03: the program skeleton that every program from this chapter on runs. Its flags
// (the common ones, the camera, window or not), then either the interactive window or a
// headless run (measurements, the --output image), and the report at the end. A chapter's
// main.cpp says only what is its own: the scene, the camera, how a frame is rendered, and
// which rows the report gets.
//
// Usage, chapter 03's main.cpp in short:
//
//   struct ChapterOptions : ProgramOptions { int max_depth = 4; };
//
//   int run(const ChapterOptions& options) {
//     validate_camera(options.camera);
//     const Backend backend = resolve_backend(options.common.backend, std::cout);
//     const SphereScene<float> scene = make_default_scene();
//     Report report = start_report("Chapter 03: spheres", "Mrays/s", "...", backend);
//     const ProgramParts parts{
//         .chapter = "ch03",
//         .window_title = "spheres",
//         .camera = options.camera,
//         .render = [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
//           render_spheres(b, scene, make_camera<float>(spec, extent), extent, ..., pixels);
//         },
//         .window_row = [&](const WindowResult& shown) { return window_row(...); },
//         .measure = [&](Report& report) { /* the headless rows */ },
//     };
//     return run_window_or_headless(options, backend, parts, report);
//   }
//
//   int main(int argc, char** argv) {
//     CLI::App app{"Chapter 03: spheres...", "ch03_spheres"};
//     ChapterOptions options;
//     add_program_options(app, options);
//     app.add_option("--depth", options.max_depth, "Mirror bounces after the primary ray");
//     return run_program_main(app, argc, argv, options, [&] { return run(options); });
//   }
//
// A render that needs the scene in device memory makes that copy on its first GPU frame
// (chapter 04's main.cpp), so a run that renders no frame never makes it.
//
// A program with more modes (chapter 07's --benchmark and ray files) picks them in run()
// before this flow. One whose headless run is its own (it prints more after the report, or
// writes the image last) composes the steps instead: show_in_window(), write_image_only(),
// write_program_image() and rt::finish_report().
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "camera_spec.h"
#include "rt/backend.h"
#include "rt/cli.h"
#include "rt/image.h"
#include "rt/report.h"
#include "window_loop.h"

namespace rt::ch03 {

// The flags every program from chapter 03 on shares.
struct ProgramOptions {
  CommonOptions common;
  CameraSpec camera;
  DisplayChoice display;
  bool image_only = false; // --image-only (add_image_only_option): the image, nothing measured
  // Which flags the command line gave (run_program_main() notes them): a program that frames
  // its scene or sizes its image itself keeps what the reader chose.
  bool eye_given = false, target_given = false, fov_given = false;
  bool width_given = false, height_given = false;

  bool size_given() const { return width_given || height_given; }
};

// Adds the common flags (--width ... --json) and the camera's (--eye ... --camera).
void add_program_options(CLI::App& app, ProgramOptions& options);

// Adds --image-only: headless, write the --output image and measure nothing.
void add_image_only_option(CLI::App& app, ProgramOptions& options);

// Adds --headless and --window last (their footer, the window's keys, closes the help), parses
// the command line, notes which flags were given, checks --output and runs `body`: the exit
// codes and error lines of rt::run_main().
int run_program_main(CLI::App& app, int argc, char** argv, ProgramOptions& options,
                     const std::function<int()>& body);

// What a chapter's program renders and measures; the skeleton calls each part when its step
// comes.
struct ProgramParts {
  std::string chapter;      // "ch03": starts the window's title; S saves ch03_screenshot_N.png
  std::string window_title; // the rest of the window's title: "ch03: spheres"
  CameraSpec camera;        // where the window starts; the camera of the --output image
  // One frame on the resolved backend (into device memory on the GPU): the window's frames,
  // and the --output image of a headless run.
  FrameRenderer render = {};
  // Instead of render, for a chapter that computes radiance: the same frame, and each pixel's
  // linear colour into `radiance` (on the backend, like pixels) when it is not null. The
  // skeleton draws the window's frames with a null `radiance`, and writes the values to an
  // --output .pfm or .exr file.
  LinearFrameRenderer render_with_radiance = {};
  // The window's row of the report, from what it showed last (asked only if it showed any).
  std::function<ReportRow(const WindowResult& shown)> window_row = {};
  // Context lines a window's report adds after its mode line.
  std::vector<std::pair<std::string, std::string>> window_context = {};
  // Headless: the chapter's measurements, context lines (after the mode line) and rows.
  std::function<void(Report& report)> measure = {};
  // The --output image of a headless run when it is not render()'s frame of `camera` (a frame
  // measure() kept, say). Asked only when there is an --output.
  std::function<Image()> image = {};
  // The linear values of the --output image (radiance, before any tone curve), asked instead
  // of image() when --output names a .pfm or .exr file, when they are not
  // render_with_radiance()'s frame of `camera`. Without either, those files hold the picture's
  // 8-bit values as floats.
  std::function<LinearImage()> linear_image = {};
  std::string image_note = {}; // "wrote FILE (image_note)"; empty: "wrote FILE"
};

// The whole run: the window when there is one (its row, the --output screenshot after
// --frames N), else --image-only's image alone, or the measurements and the --output image;
// then the report, printed and written to --json. Returns the exit code.
int run_window_or_headless(const ProgramOptions& options, Backend backend,
                           const ProgramParts& parts, Report& report);

// The steps of run_window_or_headless(), for a program that composes its own flow.
//
// Opens the window the options ask for and runs it: the mode line and window_context, the
// window's row, the --output screenshot. False, with nothing done, when the run is headless.
bool show_in_window(const ProgramOptions& options, Backend backend, const ProgramParts& parts,
                    Report& report);
// --image-only: the --output image alone (a UsageError without --output).
void write_image_only(const ProgramOptions& options, Backend backend,
                      const ProgramParts& parts);
// The headless --output image and its "wrote" line.
void write_program_image(const ProgramOptions& options, Backend backend,
                         const ProgramParts& parts);

// The window's row: `variant` with ", window (interop)" or ", window (host upload)" added, the
// frame time, and millions of pixels per second over the last frame. The error column is left
// to the caller...
ReportRow window_row(const std::string& variant, Backend backend, const WindowResult& shown);
// ... or gives the frames per second on screen ...
ReportRow window_fps_row(const std::string& variant, Backend backend,
                         const WindowResult& shown);
// ... or says how many pixels of the last frame differ from the reference.
ReportRow window_row(const std::string& variant, Backend backend, const WindowResult& shown,
                     std::size_t pixels_differing);

} // namespace rt::ch03
