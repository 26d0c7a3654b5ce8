// Chapter 02: CUDA-OpenGL interop. Shows an animation in a window through three display paths
// (the kernel writing GL's pixel buffer directly, a GPU render copied through host memory, and
// the CPU backend) and reports each one's frame time and its pixels against the CPU reference.
// Without a display it renders headless and writes the last frame.
#include <algorithm>
#include <iostream>
#include <memory>
#include <string>

#include "display_choice.h"
#include "display_paths.h"
#include "frames.h"
#include "rt/cli.h"
#include "rt/device_buffer.h"
#include "rt/program_output.h"
#include "rt/timer.h"

namespace {

using namespace rt;
using namespace rt::ch02;

struct ChapterOptions {
  CommonOptions common;
  DisplayChoice display;
  std::string path = "all"; // all, interop, copy, cpu
  std::string torn_output;  // --torn-output: the picture of a frame read while it is written
};

constexpr int k_default_frames = 120;

ReportRow error_row(std::string variant, Backend backend, const Timing& timing, Extent extent,
                    const Image& shown, int frame) {
  const Image reference = render_frame_image(Backend::cpu, extent, frame);
  const auto differing = count_differing_pixels(shown.pixels, reference.pixels);
  return {std::move(variant),
          to_string(backend),
          timing.median_ms,
          extent.pixel_count() / (timing.median_ms * 1e3),
          group_digits(static_cast<long long>(differing)) + " px differ (frame " +
              std::to_string(frame) + ")",
          {{"pixels_differing", double(differing)}}};
}

// Headless: frames into memory, timed as book appendix A says; the last one is written out.
void run_headless(const ChapterOptions& options, Backend backend, Report& report) {
  const Extent extent = options.common.extent();
  const int frames = options.common.frames > 0 ? options.common.frames : k_default_frames;
  Image last(extent.width, extent.height);
  int frame = 0;
  if (backend == Backend::gpu) {
    DeviceBuffer<Rgba8> d_frame(last.pixels.size());
    const Timing kernel = time_gpu(
        [&] { render_frame(Backend::gpu, d_frame.data(), extent, frame++); }, {5, frames});
    d_frame.download(last.pixels);
    report.add_row(
        error_row("GPU frame into device memory", backend, kernel, extent, last, frame - 1));
    frame = 0;
    const Timing copied = time_gpu(
        [&] {
          render_frame(Backend::gpu, d_frame.data(), extent, frame++);
          d_frame.download(last.pixels); // over the bus into pageable host memory
        },
        {5, frames});
    report.add_row(
        error_row("GPU frame + copy to host", backend, copied, extent, last, frame - 1));
  }
  Image cpu_frame(extent.width, extent.height);
  frame = 0;
  const Timing cpu =
      time_cpu([&] { render_frame(Backend::cpu, cpu_frame.pixels.data(), extent, frame++); },
               {1, std::max(5, frames / 10)});
  report.add_row({"CPU frame",
                  "cpu",
                  cpu.median_ms,
                  extent.pixel_count() / (cpu.median_ms * 1e3),
                  "reference",
                  {{"pixels_differing", 0.0}}});
  if (!options.common.output.empty()) // frame N-1, as the window's last frame
    write_output_image(options.common.output, render_frame_image(backend, extent, frames - 1),
                       "frame " + std::to_string(frames - 1));
  if (!options.torn_output.empty())
    write_output_image(options.torn_output, torn_frame(extent, frames - 1),
                       "frame " + std::to_string(frames - 1) + " torn over frame " +
                           std::to_string(frames - 2));
}

// The window: each display path's last frame on screen against the CPU's frame.
void run_window(const ChapterOptions& options, Backend backend, Viewer& viewer,
                Report& report) {
  const std::vector<ShownPath> shown =
      show_display_paths(viewer, backend, options.path, options.common.frames);
  for (const ShownPath& path : shown) {
    if (path.screen.width == path.extent.width && path.screen.height == path.extent.height)
      report.add_row(error_row(path_name(path.path),
                               path.path == DisplayPath::cpu ? Backend::cpu : Backend::gpu,
                               path.frame_time, path.extent, path.screen, path.frame));
    if (options.common.frames > 0 && path.last && !options.common.output.empty())
      write_output_image(options.common.output, path.screen,
                         "screenshot of frame " + std::to_string(path.frame));
  }
}

int run(const ChapterOptions& options) {
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  Report report =
      start_report("Chapter 02: CUDA-OpenGL interop", "Mpix/s", "CPU reference", backend);
  report.add_context("image", to_string(options.common.extent()));

  const std::unique_ptr<Viewer> viewer =
      open_viewer(options.display, options.common.extent(), "ch02: CUDA-OpenGL interop");
  if (viewer) {
    report.add_context("mode", k_window_mode);
    run_window(options, backend, *viewer, report);
  } else {
    report.add_context("mode", k_headless_mode);
    run_headless(options, backend, report);
  }
  finish_report(report, options.common);
  for (const ReportRow& row : report.rows())
    if (row.metrics.at(0).second != 0)
      throw Error(row.variant + ": the frame differs from the CPU's");
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 02: CUDA-OpenGL interop, a window and its headless twin",
               "ch02_pbo_interop"};
  ChapterOptions options;
  options.common.width = 1280;
  options.common.height = 720;
  options.common.output = "ch02_pbo_interop.png";
  add_common_options(app, options.common);
  add_display_flags(app, options.display, "Render without a window and write the last frame");
  app.add_option("--path", options.path, "Display path(s) in the window")
      ->check(CLI::IsMember({"all", "interop", "copy", "cpu"}))
      ->capture_default_str();
  app.add_option("--torn-output", options.torn_output,
                 "Headless: also write a torn frame, half its warps' pixels still the frame "
                 "before (what reading the buffer during the kernel's write could show)");
  app.footer("Window keys: Esc quits, S saves a screenshot, V toggles vsync, P changes the "
             "display path. With --frames N the window runs N frames per path and closes.");
  return run_main(app, argc, argv, options.common, [&] {
    if (!options.torn_output.empty()) check_image_path(options.torn_output);
    return run(options);
  });
}
