// Chapter 03: spheres seen through a real camera. Renders the default scene (a ground sphere
// of radius 1e5, mirror and coloured spheres, far moons) with the textbook and the stable
// ray/sphere intersection, on the GPU and the CPU, and reports each against the float64
// reference of the same scene. With --window it opens the interactive viewer.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "camera_cli.h"
#include "render.h"
#include "rt/backend_image.h"
#include "rt/cli.h"
#include "rt/device_buffer.h"
#include "rt/report.h"
#include "rt/timer.h"
#include "viewer.h"
#include "window_loop.h"

namespace {

using namespace rt;
using namespace rt::ch03;

struct ChapterOptions {
  CommonOptions common;
  CameraSpec camera;
  int max_depth = 4;
  SphereVariant image_variant = SphereVariant::stable;
  DisplayChoice display;
};

ReportRow error_row(std::string variant, Backend backend, const Timing& timing, Extent extent,
                    const FrameError& e) {
  const std::string text =
      group_digits(e.pixels_differing) + " px differ, " + group_digits(e.false_hits) +
      " false hits, " + group_digits(e.false_misses) + " false misses, max rel t err " +
      format_scientific(e.max_relative_t_error) + ", " + group_digits(e.nan_pixels) + " NaN";
  return {std::move(variant),
          to_string(backend),
          timing.median_ms,
          extent.pixel_count() / (timing.median_ms * 1e3),
          text,
          {{"pixels_differing", double(e.pixels_differing)},
           {"false_hits", double(e.false_hits)},
           {"false_misses", double(e.false_misses)},
           {"max_relative_t_error", e.max_relative_t_error},
           {"nan_pixels", double(e.nan_pixels)}}};
}

// One variant on one backend: timed, then compared with the reference.
ReportRow measure(SphereVariant variant, Backend backend, const SphereScene<float>& scene,
                  const CameraSpec& spec, Extent extent, int max_depth, int frames,
                  const ReferenceFrame& reference) {
  const Camera<float> camera = make_camera<float>(spec, extent);
  const RenderSettings settings{variant, max_depth};
  Image image(extent.width, extent.height);
  std::vector<PixelRecord> records(image.pixels.size());
  Timing timing;
  if (backend == Backend::gpu) {
    DeviceBuffer<Rgba8> d_pixels(image.pixels.size());
    DeviceBuffer<PixelRecord> d_records(records.size());
    timing = time_on(
        backend,
        [&] {
          render_spheres(backend, scene, camera, extent, settings, d_pixels.data(),
                         d_records.data());
        },
        frames);
    d_pixels.download(image.pixels);
    d_records.download(records);
  } else {
    timing = time_on(
        backend,
        [&] {
          render_spheres(backend, scene, camera, extent, settings, image.pixels.data(),
                         records.data());
        },
        frames);
  }
  return error_row(to_string(variant), backend, timing, extent,
                   compare_with_reference(image, records, reference));
}

void run_window(const ChapterOptions& options, Backend backend, ch02::Viewer& viewer,
                const SphereScene<float>& scene, Report& report) {
  const RenderSettings settings{options.image_variant, options.max_depth};
  const WindowSettings window{"ch03: spheres", options.common.frames, "ch03_screenshot"};
  const WindowResult shown = run_window(
      viewer, backend, options.camera, window,
      [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
        render_spheres(b, scene, make_camera<float>(spec, extent), extent, settings, pixels);
      });
  if (shown.frames == 0) return;
  // The last frame on screen against the float64 reference of the same camera.
  const Extent extent{shown.last_screen.width, shown.last_screen.height};
  const ReferenceFrame reference =
      render_reference(scene, shown.camera, extent, options.max_depth);
  FrameError error;
  error.pixels_differing = static_cast<long long>(
      count_differing_pixels(shown.last_screen.pixels, reference.image.pixels));
  ReportRow row =
      error_row(std::string(to_string(options.image_variant)) + ", window (" + shown.path + ")",
                backend, shown.frame_time, extent, error);
  row.error = group_digits(error.pixels_differing) + " px differ on screen";
  row.metrics = {{"pixels_differing", double(error.pixels_differing)}}; // nothing else measured
  report.add_row(std::move(row));
  if (options.common.frames > 0 && !options.common.output.empty()) {
    write_image(options.common.output, shown.last_screen);
    std::cout << "wrote " << options.common.output << " (screenshot)\n";
  }
}

void run_headless(const ChapterOptions& options, Backend backend,
                  const SphereScene<float>& scene, const ReferenceFrame& reference,
                  const Timing& reference_time, Report& report) {
  const Extent extent = options.common.extent();
  std::vector<Backend> backends;
  if (backend == Backend::gpu) backends.push_back(Backend::gpu);
  backends.push_back(Backend::cpu);
  for (Backend b : backends)
    for (SphereVariant variant : {SphereVariant::textbook, SphereVariant::stable})
      report.add_row(measure(variant, b, scene, options.camera, extent, options.max_depth,
                             options.common.frames, reference));
  report.add_row({"float64 reference (stable)",
                  "cpu",
                  reference_time.median_ms,
                  extent.pixel_count() / (reference_time.median_ms * 1e3),
                  "reference",
                  {}});
  if (!options.common.output.empty()) {
    const Camera<float> camera = make_camera<float>(options.camera, extent);
    const RenderSettings settings{options.image_variant, options.max_depth};
    write_image(options.common.output, render_into_image(backend, extent, [&](Rgba8* pixels) {
                  render_spheres(backend, scene, camera, extent, settings, pixels);
                }));
    std::cout << "wrote " << options.common.output << " (" << to_string(options.image_variant)
              << ")\n";
  }
}

int run(const ChapterOptions& options) {
  validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  const SphereScene<float> scene = make_default_scene();
  Report report("Chapter 03: spheres", "Mrays/s", "float64 reference (CPU)");
  report.add_context("device", describe_backend(backend));
  report.add_context(
      "image", std::to_string(options.common.width) + "x" +
                   std::to_string(options.common.height) + ", " +
                   (options.camera.kind == CameraKind::pinhole ? "pinhole" : "orthographic") +
                   " camera, mirror depth " + std::to_string(options.max_depth));
  report.add_context("scene", "ground sphere r=1e5, 3 spheres, 3 moons at r/D 1/300..1/3000");

  const std::unique_ptr<ch02::Viewer> viewer =
      open_viewer(options.display, options.common.extent(), "ch03: spheres");
  if (viewer) {
    report.add_context("mode", k_window_mode);
    run_window(options, backend, *viewer, scene, report);
  } else {
    report.add_context("mode", k_headless_mode);
    ReferenceFrame reference;
    const Timing reference_time = time_cpu(
        [&] {
          reference = render_reference(scene, options.camera, options.common.extent(),
                                       options.max_depth);
        },
        {0, 1});
    run_headless(options, backend, scene, reference, reference_time, report);
  }
  report.print(std::cout);
  if (!options.common.json.empty()) report.write_json(options.common.json);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 03: spheres, a real camera, textbook vs stable intersection",
               "ch03_spheres"};
  ChapterOptions options;
  options.common.output = "ch03_spheres.png";
  add_common_options(app, options.common);
  add_camera_options(app, options.camera);
  app.add_option("--depth", options.max_depth, "Mirror bounces after the primary ray")
      ->check(CLI::Range(0, 16))
      ->capture_default_str();
  app.add_option("--variant", options.image_variant, "Intersection used for the image")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, SphereVariant>{{"textbook", SphereVariant::textbook},
                                               {"stable", SphereVariant::stable}},
          CLI::ignore_case))
      ->default_str("stable");
  add_display_options(app, options.display);
  return run_main(app, argc, argv, [&] {
    if (!options.common.output.empty()) check_image_path(options.common.output);
    return run(options);
  });
}
