// Chapter 03: the headless report's rows. See sphere_report.h.
#include "sphere_report.h"

#include <string>
#include <vector>

#include "render.h"
#include "rt/device_buffer.h"
#include "rt/timer.h"

namespace rt::ch03 {
namespace {

ReportRow error_row(std::string variant, Backend backend, const Timing& timing, long long rays,
                    const FrameError& e) {
  const std::string text =
      group_digits(e.pixels_differing) + " px differ, " + group_digits(e.false_hits) +
      " false hits, " + group_digits(e.false_misses) + " false misses, max rel t err " +
      format_scientific(e.max_relative_t_error) + ", " + group_digits(e.nan_pixels) + " NaN";
  return {std::move(variant),
          to_string(backend),
          timing.median_ms,
          double(rays) / (timing.median_ms * 1e3),
          text,
          {{"pixels_differing", double(e.pixels_differing)},
           {"false_hits", double(e.false_hits)},
           {"false_misses", double(e.false_misses)},
           {"max_relative_t_error", e.max_relative_t_error},
           {"nan_pixels", double(e.nan_pixels)},
           {"rays", double(rays)}}};
}

// One variant on one backend: timed, then compared with the reference.
ReportRow measure(TraceSettings settings, Backend backend, const SphereScene<float>& scene,
                  const CameraSpec& spec, Extent extent, int frames,
                  const ReferenceFrame& reference) {
  const Camera<float> camera = make_camera<float>(spec, extent);
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
  long long rays = 0;
  for (const PixelRecord& record : records) rays += record.rays;
  return error_row(to_string(settings.variant), backend, timing, rays,
                   compare_with_reference(image, records, reference));
}

} // namespace

void report_sphere_variants(Backend backend, const SphereScene<float>& scene,
                            const CameraSpec& spec, Extent extent, TraceSettings settings,
                            int frames, Report& report) {
  ReferenceFrame reference;
  const Timing reference_time = time_cpu(
      [&] { reference = render_reference(scene, spec, extent, settings.max_depth); }, {0, 1});
  report.add_context("rays", group_digits(extent.pixel_count()) + " primary + " +
                                 group_digits(reference.rays - extent.pixel_count()) +
                                 " mirror rays a frame (float64 reference)");
  std::vector<Backend> backends;
  if (backend == Backend::gpu) backends.push_back(Backend::gpu);
  backends.push_back(Backend::cpu);
  for (Backend b : backends)
    for (SphereVariant variant : {SphereVariant::textbook, SphereVariant::stable}) {
      settings.variant = variant;
      report.add_row(measure(settings, b, scene, spec, extent, frames, reference));
    }
  report.add_row({"float64 reference (stable)",
                  "cpu",
                  reference_time.median_ms,
                  double(reference.rays) / (reference_time.median_ms * 1e3),
                  "reference",
                  {}});
}

} // namespace rt::ch03
