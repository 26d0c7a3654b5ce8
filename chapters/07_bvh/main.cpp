// Chapter 07: the bounding volume hierarchy. By default it loads a ~100k-triangle model (the
// course's torus knot, or any OBJ file with --scene), builds the tree by median split and by
// SAH, and traces the camera's rays through each against brute force and a float64 reference,
// then renders chapter 06's shading through the tree. Other modes:
//   --window                       the interactive viewer, shaded through the tree
//   --rays FILE --hits FILE        any batch of rays from a file, hits to a file
//   --dump-hits FILE --ray-type T  the benchmark protocol's rays for one view, hits to a file
//   --benchmark [SCENE...]         the benchmark protocol (default: the benchmark set)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bvh_build.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "camera_cli.h"
#include "chapter_report.h"
#include "model_render.h"
#include "obj_loader.h"
#include "protocol.h"
#include "ray_io.h"
#include "rt/backend_image.h"
#include "rt/cli.h"
#include "rt/report.h"
#include "rt/timer.h"
#include "runner.h"
#include "shaded_render.h"
#include "variant_cli.h"
#include "viewer.h"
#include "window_loop.h"

namespace {

using namespace rt;
using namespace rt::ch07;
using ch04::MeshHit;
using ch04::TriangleVariant;
using ch06::ShadedScene;

struct ChapterOptions {
  CommonOptions common;
  ch03::CameraSpec camera;
  bool eye_given = false, target_given = false, fov_given = false, size_given = false;
  std::string scene_path = RT_ASSETS_DIR "/torus_knot_100k.obj.gz";
  BuildOptions build;
  TriangleVariant variant = TriangleVariant::watertight;
  bool smooth = true, shadows = true;
  long long reference_pixels = 1024; // rays traced by the float64 reference
  bool skip_cpu = false;
  bool image_only = false;
  ch03::DisplayChoice display;
  // Ray queries from outside.
  std::string rays_path, hits_path, dump_hits_path;
  RayType ray_type = RayType::primary;
  // The benchmark.
  bool benchmark = false;
  std::vector<std::string> benchmark_scenes;
  std::string models_dir = RT_MODELS_DIR;
  bool end_to_end = true;
};

void render_image(const ChapterOptions& options, Backend backend, const ShadedScene& scene,
                  const Bvh& bvh, const ch03::CameraSpec& spec) {
  const Extent extent = options.common.extent();
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  const unsigned features = ch06::features_used(scene, options.smooth, options.shadows);
  const Image image = render_into_image(backend, extent, [&](Rgba8* pixels) {
    if (backend == Backend::gpu) {
      const ch06::DeviceShadedScene d_scene(scene, features);
      const DeviceBvh d_bvh(bvh);
      render_bvh_shaded(backend, features, with_bvh(d_scene.view(), d_bvh.view()), camera,
                        extent, pixels);
    } else {
      render_bvh_shaded(backend, features,
                        with_bvh(ch06::host_view(scene, features), bvh.view()), camera, extent,
                        pixels);
    }
  });
  write_image(options.common.output, image);
  std::cout << "wrote " << options.common.output << "\n";
}

void run_window(const ChapterOptions& options, Backend backend, ch02::Viewer& viewer,
                const ShadedScene& scene, const Bvh& bvh, const ch03::CameraSpec& start,
                Report& report) {
  const unsigned features = ch06::features_used(scene, options.smooth, options.shadows);
  std::optional<ch06::DeviceShadedScene> d_scene;
  std::optional<DeviceBvh> d_bvh;
  if (backend == Backend::gpu) {
    d_scene.emplace(scene, features);
    d_bvh.emplace(bvh);
  }
  const BvhSceneView view = d_scene ? with_bvh(d_scene->view(), d_bvh->view())
                                    : with_bvh(ch06::host_view(scene, features), bvh.view());
  const ch03::WindowSettings window{"ch07: bounding volume hierarchy", options.common.frames,
                                    "ch07_screenshot"};
  const ch03::WindowResult shown = ch03::run_window(
      viewer, backend, start, window,
      [&](Backend b, const ch03::CameraSpec& spec, Extent extent, Rgba8* pixels) {
        render_bvh_shaded(b, features, view, ch03::make_camera<float>(spec, extent), extent,
                          pixels);
      });
  if (shown.frames == 0) return;
  report.add_row({"shaded frame, BVH (SAH), window (" + shown.path + ")",
                  to_string(backend),
                  shown.frame_time.median_ms,
                  double(shown.last_screen.width) * shown.last_screen.height /
                      (shown.frame_time.median_ms * 1e3),
                  format_fixed(1000.0 / shown.frame_time.median_ms, 1) + " frames/s on screen",
                  {{"fps", 1000.0 / shown.frame_time.median_ms}}});
  if (options.common.frames > 0 && !options.common.output.empty()) {
    write_image(options.common.output, shown.last_screen);
    std::cout << "wrote " << options.common.output << " (screenshot)\n";
  }
}

// --rays FILE --hits FILE: the closest hit of every ray of the file.
int run_ray_file(const ChapterOptions& options, Backend backend, const ch04::Mesh& mesh) {
  if (options.hits_path.empty()) throw UsageError("--rays needs --hits FILE for the results");
  const std::vector<RayF> rays = read_ray_file(options.rays_path);
  const Bvh bvh = build_bvh(mesh, options.build);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<MeshHit> hits =
      trace_rays(backend, Query::closest, options.variant, bvh, rays);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
  write_hit_file(options.hits_path, hits);
  const auto hit_count =
      std::count_if(hits.begin(), hits.end(), [](const MeshHit& h) { return h.triangle >= 0; });
  std::cout << "traced " << group_digits(static_cast<long long>(rays.size())) << " rays on "
            << describe_backend(backend) << ": " << group_digits(hit_count) << " hit, "
            << format_fixed(ms, 1) << " ms with the upload; wrote " << options.hits_path
            << "\n";
  return 0;
}

// --dump-hits FILE --ray-type T: the protocol's rays for one view, per-pixel hits.
int run_dump_hits(const ChapterOptions& options, Backend backend, const ch04::Mesh& mesh) {
  const Bvh bvh = build_bvh(mesh, options.build);
  ProtocolView view = protocol_view(options.scene_path, bvh.bounds);
  if (options.eye_given || options.target_given || options.fov_given) {
    if (options.eye_given) view.eye = options.camera.eye.as<float>();
    if (options.target_given) view.target = options.camera.target.as<float>();
    if (options.fov_given) view.vfov_degrees = static_cast<float>(options.camera.fov_degrees);
    view.kind = ViewKind::custom;
  }
  const Extent extent = options.size_given ? options.common.extent() : Extent{1920, 1080};
  const PinholeCamera camera = make_protocol_camera(view, extent.width, extent.height);
  const std::vector<RayF> rays = camera_rays_cpu(camera);
  std::vector<MeshHit> hits = trace_rays(backend, Query::closest, options.variant, bvh, rays);
  if (options.ray_type != RayType::primary) {
    const SecondaryRays secondary =
        secondary_rays_cpu(options.ray_type, mesh, hits, camera, scene_radius(bvh.bounds));
    const Query query = options.ray_type == RayType::ao ? Query::any : Query::closest;
    const std::vector<MeshHit> secondary_hits =
        trace_rays(backend, query, options.variant, bvh, secondary.rays);
    hits = scatter_to_pixels(secondary_hits, secondary.pixel, int(extent.pixel_count()));
  }
  write_hit_file(options.dump_hits_path, hits);
  std::cout << "wrote " << options.dump_hits_path << ": " << to_string(options.ray_type)
            << " hits, " << extent.width << "x" << extent.height << ", view "
            << to_string(view.kind) << " (eye " << view.eye.x << "," << view.eye.y << ","
            << view.eye.z << ", target " << view.target.x << "," << view.target.y << ","
            << view.target.z << ", fov " << view.vfov_degrees << ")\n";
  return 0;
}

int run_benchmark_mode(const ChapterOptions& options, Backend backend) {
  const std::vector<std::string> scenes = options.benchmark_scenes.empty()
                                              ? benchmark_set(options.models_dir)
                                              : options.benchmark_scenes;
  RunnerOptions runner;
  runner.extent = options.size_given ? options.common.extent() : Extent{1920, 1080};
  runner.backend = backend;
  runner.variant = options.variant;
  runner.build = options.build;
  runner.frames = options.common.frames;
  runner.check_rays = 4096;
  runner.end_to_end = options.end_to_end;
  runner.build_rows = true;
  Report report("Chapter 07: benchmark protocol", "Mrays/s",
                "chapter 07's hits; brute force on sampled rays");
  add_runner_context(report, runner);
  const std::vector<SceneResult> results =
      run_benchmark(scenes, {chapter07_tracers}, runner, report);
  report.print(std::cout);
  std::cout << "\n"
            << summary_table(results, to_string(options.build.method),
                             describe_backend(backend), course_anchors(std::cout));
  if (!options.common.json.empty()) report.write_json(options.common.json);
  for (const SceneResult& r : results)
    if (r.problems > 0) throw Error("the tree disagrees with brute force on sampled rays");
  return 0;
}

int run(ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  check_build_options(options.build);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  if (options.benchmark) return run_benchmark_mode(options, backend);
  if (!options.rays_path.empty() || !options.dump_hits_path.empty()) {
    const ch05::ObjMesh obj = ch05::load_obj(options.scene_path);
    return options.rays_path.empty() ? run_dump_hits(options, backend, obj.geometry)
                                     : run_ray_file(options, backend, obj.geometry);
  }

  ch03::CameraSpec camera = options.camera;
  const ShadedScene scene = ch06::load_framed_obj(options.scene_path, camera, options.eye_given,
                                                  options.target_given);
  ch03::validate_camera(camera);

  Report report("Chapter 07: bounding volume hierarchy", "Mrays/s",
                "float64 brute force (CPU, sampled rays)");
  report.add_context("device", describe_backend(backend));
  report.add_context("image", std::to_string(options.common.width) + "x" +
                                  std::to_string(options.common.height));
  report.add_context("scene",
                     options.scene_path + ", " +
                         group_digits(static_cast<long long>(scene.mesh.triangles.size())) +
                         " triangles");
  report.add_context("tree", "leaves of up to " + std::to_string(options.build.max_leaf_size) +
                                 " triangles, " + std::to_string(options.build.bins) +
                                 " SAH bins; triangle test " +
                                 ch04::to_string(options.variant));
  report.add_context("error column",
                     "triangle ids differing from the float64 reference on " +
                         group_digits(options.reference_pixels) +
                         " sampled rays, worst relative t error; pixels whose hit differs "
                         "from brute force; work per ray");

  const std::unique_ptr<ch02::Viewer> viewer = ch03::open_viewer(
      options.display, options.common.extent(), "ch07: bounding volume hierarchy");
  if (viewer) {
    const Bvh bvh = build_bvh(scene.mesh, options.build);
    report.add_context("mode", ch03::k_window_mode);
    run_window(options, backend, *viewer, scene, bvh, camera, report);
  } else {
    if (options.image_only) {
      if (options.common.output.empty()) throw UsageError("--image-only needs --output");
      render_image(options, backend, scene, build_bvh(scene.mesh, options.build), camera);
      return 0;
    }
    report.add_context("mode", ch03::k_headless_mode);
    ChapterReportOptions chapter{
        options.scene_path,       options.common.extent(), options.build,
        options.variant,          options.smooth,          options.shadows,
        options.reference_pixels, options.common.frames};
    report_chapter(chapter, report_backends(backend, options.skip_cpu), scene,
                   ch03::make_camera<float>(camera, options.common.extent()), report);
    if (!options.common.output.empty())
      render_image(options, backend, scene, build_bvh(scene.mesh, options.build), camera);
  }
  report.print(std::cout);
  if (!options.common.json.empty()) report.write_json(options.common.json);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 07: the bounding volume hierarchy: build, traversal, benchmark",
               "ch07_bvh"};
  ChapterOptions options;
  options.common.width = 1280;
  options.common.height = 720;
  options.common.output = "ch07_bvh.png";
  add_common_options(app, options.common);
  ch03::add_camera_options(app, options.camera);
  ch04::add_triangle_variant_option(app, options.variant);
  app.add_option("--scene", options.scene_path, "OBJ file to trace (.obj or gzip'd)")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--split",
         [&](const std::string& text) {
           options.build.method = text == "median" ? SplitMethod::median : SplitMethod::sah;
         },
         "How the tree is built for the image, the ray files and the benchmark")
      ->check(CLI::IsMember({"median", "sah"}))
      ->default_str("sah");
  app.add_option("--leaf-size", options.build.max_leaf_size, "Most triangles in a leaf")
      ->check(CLI::Range(1, k_max_leaf_size))
      ->capture_default_str();
  app.add_option("--bins", options.build.bins, "SAH bins per axis")
      ->check(CLI::Range(2, 256))
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--shading", [&](const std::string& text) { options.smooth = text == "smooth"; },
         "Normals for the image: flat or smooth")
      ->check(CLI::IsMember({"flat", "smooth"}))
      ->default_str("smooth");
  add_on_off_option(app, "--shadows", options.shadows, "Shadow rays for the image");
  app.add_option("--reference-pixels", options.reference_pixels,
                 "Rays the float64 reference traces (every triangle, in double)")
      ->check(CLI::Range(1LL, 1LL << 20))
      ->capture_default_str();
  app.add_flag("--skip-cpu", options.skip_cpu, "On the GPU, leave out the CPU rows");
  app.add_flag("--image-only", options.image_only,
               "Headless: write the --output image and skip the measurements");
  app.add_option("--rays", options.rays_path,
                 "Trace the rays of this file (per ray: origin xyz, direction xyz, tmin, tmax; "
                 "float32 little-endian)");
  app.add_option("--hits", options.hits_path,
                 "With --rays: write the closest hit of each ray here (float32 t, int32 id)");
  app.add_option("--dump-hits", options.dump_hits_path,
                 "Write the benchmark protocol's per-pixel hits of --ray-type here");
  app.add_option_function<std::string>(
         "--ray-type",
         [&](const std::string& text) {
           options.ray_type = text == "ao"        ? RayType::ao
                              : text == "diffuse" ? RayType::diffuse
                                                  : RayType::primary;
         },
         "Rays for --dump-hits: primary, ao or diffuse")
      ->check(CLI::IsMember({"primary", "ao", "diffuse"}))
      ->default_str("primary");
  app.add_flag("--benchmark", options.benchmark,
               "Run the benchmark protocol on the SCENE files given, or on the benchmark set "
               "in --models");
  app.add_option("scenes", options.benchmark_scenes, "With --benchmark: OBJ files to measure")
      ->check(CLI::ExistingFile);
  app.add_option("--models", options.models_dir, "Where --benchmark finds the benchmark set")
      ->capture_default_str();
  add_on_off_option(app, "--end-to-end", options.end_to_end,
                    "With --benchmark: also time the shaded frame");
  ch03::add_display_options(app, options.display);
  return run_main(app, argc, argv, [&] {
    options.eye_given = app.get_option("--eye")->count() > 0;
    options.target_given = app.get_option("--target")->count() > 0;
    options.fov_given = app.get_option("--fov")->count() > 0;
    options.size_given =
        app.get_option("--width")->count() > 0 || app.get_option("--height")->count() > 0;
    if (!options.benchmark_scenes.empty() && !options.benchmark)
      throw UsageError("scene files on the command line go with --benchmark (else --scene)");
    if (!options.hits_path.empty() && options.rays_path.empty())
      throw UsageError("--hits goes with --rays FILE");
    if (!options.common.output.empty()) check_image_path(options.common.output);
    return run(options);
  });
}
