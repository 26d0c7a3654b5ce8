// Chapter 04: the headless report's rows. See triangle_report.h.
#include "triangle_report.h"

#include <string>
#include <vector>

#include "adversarial_rays.h"
#include "leak_configurations.h"
#include "rt/device_buffer.h"
#include "rt/timer.h"

namespace rt::ch04 {
namespace {

// A render of one variant on one backend: timed, then compared with the reference.
ReportRow measure_render(TriangleVariant variant, Backend backend, const TriangleScene& scene,
                         const ch03::Camera<float>& camera, Extent extent, int frames,
                         const MeshReference& reference) {
  Image image(extent.width, extent.height);
  std::vector<MeshPixelRecord> records(image.pixels.size());
  Timing timing;
  if (backend == Backend::gpu) {
    const DeviceTriangleScene d_scene(scene);
    DeviceBuffer<Rgba8> d_pixels(image.pixels.size());
    DeviceBuffer<MeshPixelRecord> d_records(records.size());
    timing = time_on(
        backend,
        [&] {
          render_triangles(backend, variant, d_scene.view(), d_scene.object(), camera, extent,
                           d_pixels.data(), d_records.data());
        },
        frames);
    d_pixels.download(image.pixels);
    d_records.download(records);
  } else {
    // Brute force on CPU cores takes seconds a frame: one timed frame unless asked for more.
    timing = time_cpu(
        [&] {
          render_triangles(backend, variant, host_view(scene.mesh), scene.object.data(), camera,
                           extent, image.pixels.data(), records.data());
        },
        {0, frames > 0 ? frames : 1});
  }
  const MeshFrameError e = compare_with_reference(image, records, reference);
  return {std::string("render, ") + to_string(variant),
          to_string(backend),
          timing.median_ms,
          extent.pixel_count() / (timing.median_ms * 1e3),
          group_digits(e.pixels_differing) + " px differ, " + group_digits(e.holes) +
              " holes, " + group_digits(e.nan_pixels) + " NaN",
          {{"pixels_differing", double(e.pixels_differing)},
           {"holes", double(e.holes)},
           {"nan_pixels", double(e.nan_pixels)}}};
}

// Rays from inside a closed mesh aimed at its vertices and edges: every one must hit. On the
// GPU the kernel alone is timed, with events (mesh and rays are uploaded before, the tallies
// copied back after); on the CPU, one run over rays already in host memory.
ReportRow measure_leaks(TriangleVariant variant, Backend backend,
                        const LeakConfiguration& configuration, int ray_count, int frames) {
  const Mesh mesh = configuration.make_mesh();
  const std::vector<RayF> rays = rays_at_vertices_and_edges(
      mesh, configuration.inside(), configuration.spread, ray_count, configuration.seed);
  LeakCount count;
  Timing timing;
  if (backend == Backend::gpu) {
    DeviceLeakTest test(mesh, rays);
    timing = time_on(
        backend, [&] { test.launch(variant); }, frames);
    count = test.count();
  } else {
    timing = time_cpu([&] { count = count_leaks_cpu(variant, mesh, rays); }, {0, 1});
  }
  const double per_million = 1e6 / double(count.rays);
  return {std::string("leaks, ") + to_string(variant) + ", " + configuration.name,
          to_string(backend),
          timing.median_ms * 1e6 / double(count.rays), // ms per million rays
          count.rays / (timing.median_ms * 1e3),
          group_digits(static_cast<long long>(count.leaks * per_million + 0.5)) +
              " leaks per million, " +
              group_digits(static_cast<long long>(count.double_hits * per_million + 0.5)) +
              " double hits per million, " + group_digits(count.non_finite) + " NaN",
          {{"leaks", double(count.leaks)},
           {"double_hits", double(count.double_hits)},
           {"non_finite_hits", double(count.non_finite)},
           {"rays", double(count.rays)}}};
}

} // namespace

void report_triangle_variants(Backend backend, const TriangleScene& scene,
                              const CameraSpec& spec, Extent extent, int frames, int leak_rays,
                              Report& report) {
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  MeshReference reference;
  const Timing reference_time =
      time_cpu([&] { reference = render_triangles_reference(scene, spec, extent); }, {0, 1});
  std::vector<Backend> backends;
  if (backend == Backend::gpu) backends.push_back(Backend::gpu);
  backends.push_back(Backend::cpu);
  for (Backend b : backends)
    for (TriangleVariant variant : k_variants)
      report.add_row(measure_render(variant, b, scene, camera, extent, frames, reference));
  report.add_row({"render, float64 reference (watertight)",
                  "cpu",
                  reference_time.median_ms,
                  extent.pixel_count() / (reference_time.median_ms * 1e3),
                  "reference",
                  {}});
  for (Backend b : backends)
    for (const LeakConfiguration& configuration : k_leak_configurations)
      for (TriangleVariant variant : k_variants)
        report.add_row(measure_leaks(variant, b, configuration, leak_rays, frames));
}

} // namespace rt::ch04
