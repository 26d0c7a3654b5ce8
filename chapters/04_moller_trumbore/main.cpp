// Chapter 04: triangles. Renders closed meshes (an icosphere, a box) and a floor quad with
// Moller-Trumbore and with the watertight test, GPU and CPU, against a float64 reference; then
// fires a million rays from inside closed meshes straight at their vertices and edges, at the
// origin and 1e5 away, and counts the rays that leak out. With --window it opens the viewer.
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "adversarial_rays.h"
#include "camera_cli.h"
#include "leak_configurations.h"
#include "mesh_render.h"
#include "rt/backend_image.h"
#include "rt/cli.h"
#include "rt/report.h"
#include "rt/timer.h"
#include "variant_cli.h"
#include "viewer.h"
#include "window_loop.h"

namespace {

using namespace rt;
using namespace rt::ch04;

struct ChapterOptions {
  CommonOptions common;
  CameraSpec camera{{0.0, 2.2, 6.5}, {0.3, 0.7, 0.0}, {0.0, 1.0, 0.0}, 40.0};
  double translate = 0.0; // the scene and the camera, moved along (1, 1, 1)
  int subdivisions = 2;
  int leak_rays = 1'000'000;
  TriangleVariant image_variant = TriangleVariant::watertight;
  ch03::DisplayChoice display;
};

CameraSpec moved(CameraSpec camera, Vec3d offset) {
  camera.eye += offset;
  camera.target += offset;
  return camera;
}

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

// Rays from inside a closed mesh aimed at its vertices and edges: every one must hit.
ReportRow measure_leaks(TriangleVariant variant, Backend backend,
                        const LeakConfiguration& configuration, int ray_count) {
  const Mesh mesh = configuration.make_mesh();
  const std::vector<RayF> rays = rays_at_vertices_and_edges(
      mesh, configuration.inside(), configuration.spread, ray_count, configuration.seed);
  LeakCount count;
  const Timing timing = time_cpu(
      [&] {
        count = backend == Backend::gpu ? count_leaks_gpu(variant, mesh, rays)
                                        : count_leaks_cpu(variant, mesh, rays);
      },
      {backend == Backend::gpu ? 1 : 0, backend == Backend::gpu ? 5 : 1});
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

void run_window(const ChapterOptions& options, Backend backend, ch02::Viewer& viewer,
                const TriangleScene& scene, const CameraSpec& start, Report& report) {
  std::optional<DeviceTriangleScene> d_scene;
  if (backend == Backend::gpu) d_scene.emplace(scene);
  const ch03::WindowSettings window{"ch04: triangles", options.common.frames,
                                    "ch04_screenshot"};
  const ch03::WindowResult shown =
      ch03::run_window(viewer, backend, start, window,
                       [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
                         const auto camera = ch03::make_camera<float>(spec, extent);
                         if (b == Backend::gpu)
                           render_triangles(b, options.image_variant, d_scene->view(),
                                            d_scene->object(), camera, extent, pixels);
                         else
                           render_triangles(b, options.image_variant, host_view(scene.mesh),
                                            scene.object.data(), camera, extent, pixels);
                       });
  if (shown.frames == 0) return;
  const Extent extent{shown.last_screen.width, shown.last_screen.height};
  const MeshReference reference = render_triangles_reference(scene, shown.camera, extent);
  const auto differing =
      count_differing_pixels(shown.last_screen.pixels, reference.image.pixels);
  report.add_row({std::string("render, ") + to_string(options.image_variant) + ", window (" +
                      shown.path + ")",
                  to_string(backend),
                  shown.frame_time.median_ms,
                  extent.pixel_count() / (shown.frame_time.median_ms * 1e3),
                  group_digits(static_cast<long long>(differing)) + " px differ on screen",
                  {{"pixels_differing", double(differing)}}});
  if (options.common.frames > 0 && !options.common.output.empty()) {
    write_image(options.common.output, shown.last_screen);
    std::cout << "wrote " << options.common.output << " (screenshot)\n";
  }
}

void run_headless(const ChapterOptions& options, Backend backend, const TriangleScene& scene,
                  const CameraSpec& camera_spec, Report& report) {
  const Extent extent = options.common.extent();
  const ch03::Camera<float> camera = ch03::make_camera<float>(camera_spec, extent);
  MeshReference reference;
  const Timing reference_time = time_cpu(
      [&] { reference = render_triangles_reference(scene, camera_spec, extent); }, {0, 1});
  std::vector<Backend> backends;
  if (backend == Backend::gpu) backends.push_back(Backend::gpu);
  backends.push_back(Backend::cpu);
  for (Backend b : backends)
    for (TriangleVariant variant : k_variants)
      report.add_row(
          measure_render(variant, b, scene, camera, extent, options.common.frames, reference));
  report.add_row({"render, float64 reference (watertight)",
                  "cpu",
                  reference_time.median_ms,
                  extent.pixel_count() / (reference_time.median_ms * 1e3),
                  "reference",
                  {}});
  for (Backend b : backends)
    for (const LeakConfiguration& configuration : k_leak_configurations)
      for (TriangleVariant variant : k_variants)
        report.add_row(measure_leaks(variant, b, configuration, options.leak_rays));
  if (!options.common.output.empty()) {
    const Image image = render_into_image(backend, extent, [&](Rgba8* pixels) {
      if (backend == Backend::gpu) {
        const DeviceTriangleScene d_scene(scene);
        render_triangles(backend, options.image_variant, d_scene.view(), d_scene.object(),
                         camera, extent, pixels);
      } else {
        render_triangles(backend, options.image_variant, host_view(scene.mesh),
                         scene.object.data(), camera, extent, pixels);
      }
    });
    write_image(options.common.output, image);
    std::cout << "wrote " << options.common.output << " (" << to_string(options.image_variant)
              << ")\n";
  }
}

int run(const ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  const Vec3d offset{options.translate, options.translate, options.translate};
  const TriangleScene scene = make_demo_scene(options.subdivisions, offset);
  const CameraSpec camera = moved(options.camera, offset);
  Report report("Chapter 04: Moller-Trumbore and the watertight test", "Mrays/s",
                "float64 reference (CPU)");
  report.add_context("device", describe_backend(backend));
  report.add_context("image", std::to_string(options.common.width) + "x" +
                                  std::to_string(options.common.height));
  std::ostringstream scene_text;
  scene_text << scene.mesh.triangles.size() << " triangles (icosphere, box, floor quad)";
  if (options.translate != 0.0)
    scene_text << ", moved by " << options.translate << " on x, y, z";
  report.add_context("scene", scene_text.str());
  report.add_context("leak rows", std::to_string(options.leak_rays) +
                                      " rays each from inside a closed mesh at its vertices "
                                      "and edges; ms/frame column: ms per million rays");

  const std::unique_ptr<ch02::Viewer> viewer =
      ch03::open_viewer(options.display, options.common.extent(), "ch04: triangles");
  if (viewer) {
    report.add_context("mode", ch03::k_window_mode);
    run_window(options, backend, *viewer, scene, camera, report);
  } else {
    report.add_context("mode", ch03::k_headless_mode);
    run_headless(options, backend, scene, camera, report);
  }
  report.print(std::cout);
  if (!options.common.json.empty()) report.write_json(options.common.json);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 04: Moller-Trumbore and the watertight ray/triangle test",
               "ch04_moller_trumbore"};
  ChapterOptions options;
  options.common.width = 1280;
  options.common.height = 720;
  options.common.output = "ch04_moller_trumbore.png";
  add_common_options(app, options.common);
  ch03::add_camera_options(app, options.camera);
  app.add_option("--translate", options.translate,
                 "Move the scene and the camera by this much along x, y and z")
      ->check(finite_range(-1e7, 1e7))
      ->capture_default_str();
  app.add_option("--subdivisions", options.subdivisions,
                 "Icosphere subdivisions (20 * 4^n triangles)")
      ->check(CLI::Range(0, 6))
      ->capture_default_str();
  app.add_option("--leak-rays", options.leak_rays, "Rays per leak configuration")
      ->check(CLI::Range(1, 100'000'000))
      ->capture_default_str();
  add_triangle_variant_option(app, options.image_variant);
  ch03::add_display_options(app, options.display);
  return run_main(app, argc, argv, [&] {
    if (!options.common.output.empty()) check_image_path(options.common.output);
    return run(options);
  });
}
