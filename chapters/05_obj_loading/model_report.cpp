// Chapter 05: the report of a loaded model. See model_report.h.
#include "model_report.h"

#include <chrono>
#include <iostream>
#include <sstream>
#include <vector>

#include "model_render.h"
#include "program.h"
#include "progress.h"
#include "rt/backend_image.h"
#include "rt/device_buffer.h"
#include "rt/program_output.h"
#include "rt/timer.h"

namespace rt::ch05 {
namespace {

using ch04::DeviceTriangleScene;
using ch04::MeshFrameError;
using ch04::MeshPixelRecord;
using ch04::MeshReference;

constexpr TriangleVariant k_variants[] = {TriangleVariant::watertight,
                                          TriangleVariant::moller_trumbore};

std::string vec_text(Vec3d v) {
  std::ostringstream text;
  text.precision(4);
  text << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return text.str();
}

// "1 triangle", "100 000 triangles".
std::string count_text(std::size_t n, const char* singular, const char* plural) {
  return group_digits(static_cast<long long>(n)) + " " + (n == 1 ? singular : plural);
}

std::string describe_model(const ObjMesh& mesh) {
  const auto objects = static_cast<std::size_t>(mesh.object_count);
  const auto degenerate = static_cast<std::size_t>(mesh.degenerate_triangle_count);
  return count_text(mesh.geometry.triangles.size(), "triangle", "triangles") + ", " +
         count_text(mesh.geometry.vertices.size(), "vertex", "vertices") + ", normals: " +
         (mesh.normals.empty() ? "no" : "yes (" + group_digits(mesh.normals.size()) + ")") +
         ", texture coordinates: " + (mesh.texcoords.empty() ? "no" : "yes") + ", " +
         count_text(objects, "object", "objects") + ", " +
         count_text(mesh.material_names.size(), "material", "materials") + ", " +
         group_digits(static_cast<long long>(degenerate)) + " degenerate";
}

// A frame of the sample's pixels, timed: on the GPU the protocol's plan (CUDA events), on the
// CPU one run unless --frames asks for more, with a progress line while it takes long.
struct TimedFrame {
  Image image;
  std::vector<MeshPixelRecord> records;
  Timing timing;
};

TimedFrame render_timed(Backend backend, TriangleVariant variant, const TriangleScene& scene,
                        const DeviceTriangleScene* d_scene, const ch03::Camera<float>& camera,
                        PixelSample sample, int frames, const std::string& what) {
  const Extent extent = sample.extent();
  TimedFrame frame{Image(extent.width, extent.height),
                   std::vector<MeshPixelRecord>(extent.pixel_count()),
                   {}};
  if (backend == Backend::gpu) {
    DeviceBuffer<Rgba8> d_pixels(frame.image.pixels.size());
    DeviceBuffer<MeshPixelRecord> d_records(frame.records.size());
    frame.timing = time_on(
        backend,
        [&] {
          render_model(backend, variant, d_scene->view(), d_scene->object(), camera, sample,
                       d_pixels.data(), d_records.data());
        },
        frames);
    d_pixels.download(frame.image.pixels);
    d_records.download(frame.records);
  } else {
    const int runs = frames > 0 ? frames : 1;
    Progress progress(what, extent.height * runs, std::cerr);
    frame.timing = time_cpu(
        [&] {
          render_model(backend, variant, ch04::host_view(scene.mesh), scene.object.data(),
                       camera, sample, frame.image.pixels.data(), frame.records.data(),
                       progress.rows_done());
        },
        {0, runs});
  }
  return frame;
}

// The frame's error over the reference's sample of its pixels.
MeshFrameError error_of(const TimedFrame& frame, PixelSample frame_sample,
                        PixelSample reference_sample, const MeshReference& reference) {
  if (frame_sample.stride == reference_sample.stride)
    return ch04::compare_with_reference(frame.image, frame.records, reference);
  const Extent e = reference_sample.extent();
  Image image(e.width, e.height);
  image.pixels = sampled(frame.image.pixels, reference_sample);
  return ch04::compare_with_reference(image, sampled(frame.records, reference_sample),
                                      reference);
}

ReportRow render_row(const std::string& name, Backend backend, const TimedFrame& frame,
                     const MeshFrameError& e) {
  const long long rays = static_cast<long long>(frame.image.pixels.size());
  return {name,
          to_string(backend),
          frame.timing.median_ms,
          rays / frame.timing.median_ms, // rays per ms: krays/s
          group_digits(e.pixels_differing) + " px differ, " + group_digits(e.holes) +
              " holes, " + group_digits(e.nan_pixels) + " NaN",
          {{"pixels_differing", double(e.pixels_differing)},
           {"holes", double(e.holes)},
           {"nan_pixels", double(e.nan_pixels)},
           {"rays", double(rays)}}};
}

// A brute-force row of the scaling table: time against triangle count.
ReportRow scaling_row(const std::string& name, Backend backend, const Timing& timing,
                      long long rays, long long triangles, const std::string& note) {
  const double ns_per_test = timing.median_ms * 1e6 / (double(rays) * double(triangles));
  std::ostringstream error;
  error.precision(3);
  error << note << ns_per_test << " ns per ray-triangle test";
  return {name,
          to_string(backend),
          timing.median_ms,
          rays / timing.median_ms,
          error.str(),
          {{"triangles", double(triangles)}, {"ns_per_test", ns_per_test}}};
}

// Icospheres of 20 * 4^k triangles where the model is, through the same camera: brute force
// tests every triangle for every ray, so the time per frame grows with the triangle count.
void add_scaling_rows(const ModelMeasurements& m, Backend backend,
                      const ch03::Camera<float>& camera, PixelSample sample, Report& report) {
  const double radius = 0.6 * m.radius;
  for (int k = 0; k <= m.scaling_max; ++k) {
    TriangleScene sphere{ch04::make_icosphere(k, m.centre, radius), {}};
    sphere.object.assign(sphere.mesh.triangles.size(), -1);
    const auto triangles = static_cast<long long>(sphere.mesh.triangles.size());
    const std::string name = "brute force, icosphere, " +
                             count_text(sphere.mesh.triangles.size(), "triangle", "triangles");
    std::optional<DeviceTriangleScene> d_sphere;
    if (backend == Backend::gpu) d_sphere.emplace(sphere);
    const TimedFrame frame =
        render_timed(backend, TriangleVariant::watertight, sphere,
                     d_sphere ? &*d_sphere : nullptr, camera, sample, m.frames, name);
    report.add_row(
        scaling_row(name, backend, frame.timing, sample.extent().pixel_count(), triangles, ""));
  }
}

// The renders' rows: both variants over the whole image on the GPU and over the sample on the
// CPU, then the reference's row. Keeps the frame --output shows, if one of them is it, and the
// time of the model's watertight frame for the brute-force rows.
struct RenderRows {
  std::optional<Image> picture;
  Timing model_time;
};

RenderRows add_render_rows(Backend backend, const TriangleScene& scene, const CameraSpec& spec,
                           const ModelMeasurements& m, Report& report) {
  const PixelSample whole{m.extent, 1};
  const PixelSample sample = sample_of(m.extent, m.reference_pixels);
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, m.extent);
  std::optional<DeviceTriangleScene> d_scene;
  if (backend == Backend::gpu) {
    check_device_memory(device_bytes_needed(scene, m.extent), m.scene_path);
    d_scene.emplace(scene);
  }

  MeshReference reference;
  Timing reference_time;
  {
    Progress progress("float64 reference", sample.extent().height, std::cerr);
    reference_time = time_cpu(
        [&] { reference = render_model_reference(scene, spec, sample, progress.rows_done()); },
        {0, 1});
  }

  RenderRows out;
  if (backend == Backend::gpu) {
    for (TriangleVariant variant : k_variants) {
      const std::string name =
          std::string("render ") + to_string(m.extent) + ", " + ch04::to_string(variant);
      TimedFrame frame =
          render_timed(backend, variant, scene, &*d_scene, camera, whole, m.frames, name);
      report.add_row(
          render_row(name, backend, frame, error_of(frame, whole, sample, reference)));
      if (variant == TriangleVariant::watertight) out.model_time = frame.timing;
      if (variant == m.image_variant) out.picture = std::move(frame.image);
    }
  }
  for (TriangleVariant variant : k_variants) {
    const std::string name = std::string("render ") + to_string(sample.extent()) +
                             (sample.stride > 1 ? " sample, " : ", ") +
                             ch04::to_string(variant);
    TimedFrame frame =
        render_timed(Backend::cpu, variant, scene, nullptr, camera, sample, m.frames, name);
    report.add_row(
        render_row(name, Backend::cpu, frame,
                   ch04::compare_with_reference(frame.image, frame.records, reference)));
    if (backend == Backend::cpu && variant == TriangleVariant::watertight)
      out.model_time = frame.timing;
    if (backend == Backend::cpu && sample.stride == 1 && variant == m.image_variant)
      out.picture = std::move(frame.image);
  }
  report.add_row({"render " + to_string(sample.extent()) + ", float64 reference (watertight)",
                  "cpu",
                  reference_time.median_ms,
                  sample.extent().pixel_count() / reference_time.median_ms,
                  "reference",
                  {}});
  return out;
}

void add_headless_context(Backend backend, const ModelMeasurements& m, PixelSample sample,
                          Report& report) {
  report.add_context("image", to_string(m.extent) +
                                  (backend == Backend::cpu && m.size_from_backend
                                       ? " (the CPU's default: --width and --height set it)"
                                       : ""));
  if (sample.stride > 1)
    report.add_context("sample", "CPU rows and the reference trace the middle pixel of "
                                 "each " +
                                     std::to_string(sample.stride) + "x" +
                                     std::to_string(sample.stride) + " block (" +
                                     to_string(sample.extent()) +
                                     "); GPU rows are compared there");
  const Extent brute_force = backend == Backend::gpu ? m.extent : sample.extent();
  report.add_context("brute force rows", "the same camera, every ray against every "
                                         "triangle, on the " +
                                             std::string(to_string(backend)) + " at " +
                                             to_string(brute_force));
}
} // namespace

void add_model_context(Report& report, const std::string& path, const ObjMesh& mesh,
                       double load_ms, const CameraSpec& camera, bool camera_from_flags) {
  report.add_context("scene", path);
  report.add_context("model", describe_model(mesh));
  report.add_context("bounds", vec_text(mesh.bounds_min.as<double>()) + " to " +
                                   vec_text(mesh.bounds_max.as<double>()));
  std::ostringstream load_text;
  load_text.precision(3);
  load_text << load_ms << " ms (read, gunzip, line checks, tinyobjloader, triangles)";
  report.add_context("load", load_text.str());
  report.add_context(
      "camera", std::string(camera_from_flags ? "from the flags" : "framed automatically") +
                    ": eye " + vec_text(camera.eye) + ", target " + vec_text(camera.target));
}

std::optional<Image> report_model(Backend backend, const TriangleScene& scene,
                                  const CameraSpec& spec, const ModelMeasurements& m,
                                  Report& report) {
  const PixelSample sample = sample_of(m.extent, m.reference_pixels);
  add_headless_context(backend, m, sample, report);
  RenderRows rows = add_render_rows(backend, scene, spec, m, report);
  if (m.scaling_max >= 0) {
    const auto triangles = static_cast<long long>(scene.mesh.triangles.size());
    const PixelSample scaling_sample =
        backend == Backend::gpu ? PixelSample{m.extent, 1} : sample;
    const ch03::Camera<float> camera = ch03::make_camera<float>(spec, m.extent);
    add_scaling_rows(m, backend, camera, scaling_sample, report);
    report.add_row(
        scaling_row("brute force, the model, " +
                        count_text(scene.mesh.triangles.size(), "triangle", "triangles"),
                    backend, rows.model_time, scaling_sample.extent().pixel_count(), triangles,
                    "the watertight row above: "));
  }
  return std::move(rows.picture);
}

Image render_image_on_cpu(const TriangleScene& scene, const CameraSpec& spec, Extent extent,
                          TriangleVariant variant) {
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  const auto start = std::chrono::steady_clock::now();
  Progress progress("image " + to_string(extent), extent.height, std::cerr);
  Image image = render_into_image(Backend::cpu, extent, [&](Rgba8* pixels) {
    render_model(Backend::cpu, variant, ch04::host_view(scene.mesh), scene.object.data(),
                 camera, PixelSample{extent, 1}, pixels, nullptr, progress.rows_done());
  });
  const auto seconds = static_cast<long long>(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() + 0.5);
  std::cout << "rendered the " << to_string(extent) << " image on the CPU in " << seconds
            << " s\n";
  return image;
}

ReportRow sampled_window_row(const ch03::WindowResult& shown, Backend backend,
                             const TriangleScene& scene, TriangleVariant variant,
                             long long reference_pixels) {
  const Extent extent = shown.extent();
  const PixelSample sample = sample_of(extent, reference_pixels);
  const MeshReference reference = render_model_reference(scene, shown.camera, sample);
  const auto differing =
      count_differing_pixels(sampled(shown.last_screen.pixels, sample), reference.image.pixels);
  ReportRow row = ch03::window_row(
      "render " + to_string(extent) + ", " + ch04::to_string(variant), backend, shown);
  row.throughput = extent.pixel_count() / shown.frame_time.median_ms; // krays/s
  row.error = group_digits(static_cast<long long>(differing)) + " of " +
              group_digits(sample.extent().pixel_count()) + " sampled px differ on screen";
  row.metrics = {{"pixels_differing", double(differing)}};
  return row;
}
} // namespace rt::ch05
