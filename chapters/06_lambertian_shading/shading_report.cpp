// Chapter 06: the headless report's rows. See shading_report.h.
#include "shading_report.h"

#include <algorithm>
#include <cstdio>
#include <optional>

#include "rt/device_buffer.h"
#include "rt/timer.h"
#include "shaded_render.h"

namespace rt::ch06 {
namespace {

// A frame rendered and timed on one backend by one kind of kernel.
struct MeasuredFrame {
  Image image;
  std::vector<ShadedPixelRecord> records;
  Timing timing;
  std::size_t bytes = 0; // scene bytes the kernel reads (uploaded, on the GPU)
  int registers = -1;    // per thread, GPU only
};

MeasuredFrame measure_frame(Backend backend, KernelKind kind, unsigned features,
                            const ShadedScene& scene, const ch03::Camera<float>& camera,
                            Extent extent, int frames) {
  MeasuredFrame out{Image(extent.width, extent.height),
                    std::vector<ShadedPixelRecord>(extent.pixel_count()),
                    {},
                    scene_bytes(scene, uploaded_features(kind, features)),
                    -1};
  if (backend == Backend::gpu) {
    const DeviceShadedScene d_scene(scene, uploaded_features(kind, features));
    DeviceBuffer<Rgba8> d_pixels(out.image.pixels.size());
    DeviceBuffer<ShadedPixelRecord> d_records(out.records.size());
    out.timing = time_on(
        backend,
        [&] {
          render_shaded(backend, kind, features, d_scene.view(), camera, extent,
                        d_pixels.data(), d_records.data());
        },
        frames);
    d_pixels.download(out.image.pixels);
    d_records.download(out.records);
    out.bytes = d_scene.bytes_uploaded();
    out.registers = kernel_registers(kind, features);
  } else {
    // Brute force on CPU cores takes a second or more a frame: one timed frame unless asked.
    const SceneView view = host_view(scene, uploaded_features(kind, features));
    out.timing = time_cpu(
        [&] {
          render_shaded(backend, kind, features, view, camera, extent, out.image.pixels.data(),
                        out.records.data());
        },
        {0, frames > 0 ? frames : 1});
  }
  return out;
}

ReportRow frame_row(const std::string& name, Backend backend, const MeasuredFrame& frame,
                    Extent extent, const ShadedFrameError& e, const std::string& extra) {
  const double rays = double(extent.pixel_count()) + double(e.shadow_rays);
  const std::string registers =
      frame.registers >= 0 ? std::to_string(frame.registers) + " regs" : "n/a regs";
  ReportRow row{name,
                to_string(backend),
                frame.timing.median_ms,
                rays / (frame.timing.median_ms * 1e3),
                group_digits(e.pixels_differing) + " px differ, RMSE " +
                    format_fixed(e.rmse, 3) + ", " + group_digits(e.nan_pixels) + " NaN; " +
                    registers + ", " + group_digits(static_cast<long long>(frame.bytes)) +
                    " B" + extra,
                {{"pixels_differing", double(e.pixels_differing)},
                 {"rmse_8bit", e.rmse},
                 {"nan_pixels", double(e.nan_pixels)},
                 {"shadow_rays", double(e.shadow_rays)},
                 {"scene_bytes", double(frame.bytes)}}};
  if (frame.registers >= 0) row.metrics.emplace_back("registers", frame.registers);
  return row;
}

} // namespace

std::string variant_name(Variant v) {
  return std::string(v.smooth ? "smooth" : "flat") + (v.shadows ? ", shadows" : ", no shadows");
}

void report_variants(const std::vector<Backend>& backends, const ShadedScene& scene,
                     const CameraSpec& spec, Extent extent, int frames, Report& report) {
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  for (const Variant variant : k_variants) {
    const unsigned features = features_used(scene, variant.smooth, variant.shadows);
    ShadedReference reference;
    const Timing reference_time = time_cpu(
        [&] { reference = render_shaded_reference(scene, features, spec, extent); }, {0, 1});
    for (const Backend backend : backends) {
      std::optional<MeasuredFrame> specialised;
      for (const KernelKind kind : {KernelKind::specialised, KernelKind::all_features}) {
        MeasuredFrame frame =
            measure_frame(backend, kind, features, scene, camera, extent, frames);
        const ShadedFrameError e =
            compare_with_reference(frame.image, frame.records, reference.image);
        std::string extra;
        if (specialised) {
          const auto differing =
              count_differing_pixels(frame.image.pixels, specialised->image.pixels);
          extra = differing == 0 ? "; image identical"
                                 : "; " + group_digits(static_cast<long long>(differing)) +
                                       " px differ from specialised";
        }
        report.add_row(frame_row(variant_name(variant) + ", " + to_string(kind), backend, frame,
                                 extent, e, extra));
        if (!specialised) specialised = std::move(frame);
      }
    }
    report.add_row({variant_name(variant) + ", float64 reference",
                    "cpu",
                    reference_time.median_ms,
                    double(reference.rays) / (reference_time.median_ms * 1e3),
                    "reference",
                    {}});
  }
}

void report_acne(const std::vector<Backend>& backends, Extent image,
                 const LightSettings& lights, Report& report) {
  const Extent extent{std::min(image.width, 320), std::min(image.height, 180)};
  for (const double scale : {1.0, 1e3, 1e6}) {
    const ShadedScene sphere = make_lone_sphere(2, scale, lights);
    const CameraSpec spec = frame_bounds_down_z(bounds_of(sphere.mesh), 40.0, extent);
    const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
    const unsigned features = features_used(sphere, false, true);
    for (const Backend backend : backends) {
      const MeasuredFrame frame =
          measure_frame(backend, KernelKind::specialised, features, sphere, camera, extent, 1);
      long long rays = 0, acne = 0;
      for (const ShadedPixelRecord& r : frame.records) {
        rays += r.shadow_rays;
        acne += r.shadowed_facing;
      }
      char name[64];
      std::snprintf(name, sizeof name, "shadow acne, convex sphere at scale %.0e", scale);
      report.add_row({name,
                      to_string(backend),
                      frame.timing.median_ms,
                      double(extent.pixel_count() + rays) / (frame.timing.median_ms * 1e3),
                      group_digits(acne) + " of " + group_digits(rays) +
                          " shadow rays blocked on faces facing their light",
                      {{"self_shadowed", double(acne)}, {"shadow_rays", double(rays)}}});
    }
  }
}

} // namespace rt::ch06
