// Chapter 08: memory spaces for the traversal. By default it loads the course's ~100k-triangle
// model (or any OBJ file with --scene), builds chapter 07's tree, and traces the benchmark
// protocol's primary, ambient occlusion and diffuse rays through every memory path (plain
// loads, read-only loads, 16-byte records, texture objects), each timed, each checked bit for
// bit against chapter 07's hits and on a sample against a float64 reference; then it renders
// the shaded image through the kept path. Other modes:
//   --window                 the interactive viewer, shaded through the kept path
//   --benchmark [SCENE...]   every path on the benchmark set (default) or the scenes given
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bvh_build.h"
#include "camera_cli.h"
#include "kept_render.h"
#include "memory_trace.h"
#include "memory_tracers.h"
#include "obj_loader.h"
#include "rt/backend_image.h"
#include "rt/cli.h"
#include "rt/report.h"
#include "runner.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "viewer.h"
#include "window_loop.h"

namespace {

using namespace rt;
using namespace rt::ch08;
using ch06::ShadedScene;

struct ChapterOptions {
  CommonOptions common;
  ch03::CameraSpec camera;
  bool eye_given = false, target_given = false, size_given = false;
  std::string scene_path = RT_ASSETS_DIR "/torus_knot_100k.obj.gz";
  std::vector<MemoryPath> paths{std::begin(k_all_paths), std::end(k_all_paths)};
  bool paths_given = false;
  long long reference_rays = 1024;
  bool skip_cpu = false;
  bool image_only = false;
  ch03::DisplayChoice display;
  bool benchmark = false;
  std::vector<std::string> benchmark_scenes;
  std::string models_dir = RT_MODELS_DIR;
};

// Paths named with --memory must exist where the run is (`all` takes what exists there).
void check_paths(const ChapterOptions& options, Backend backend) {
  if (options.paths_given)
    for (const MemoryPath path : options.paths) check_runs_on(path, backend);
}

ch07::RunnerOptions runner_options(const ChapterOptions& options, Backend backend,
                                   Extent extent) {
  check_paths(options, backend);
  ch07::RunnerOptions runner;
  runner.extent = extent;
  runner.backend = backend;
  runner.frames = options.common.frames;
  return runner;
}

void add_context(Report& report, const ch07::RunnerOptions& runner,
                 const std::vector<MemoryPath>& paths) {
  ch07::add_runner_context(report, runner);
  std::string described;
  for (const MemoryPath p : paths)
    described += std::string(described.empty() ? "" : "; ") + to_string(p) + ": " + describe(p);
  report.add_context("memory paths", described);
  report.add_context("kept path", std::string(to_string(k_kept_path)) +
                                      " (what the image and later chapters use)");
}

// The report's rows, the tables of the first backend's figures, and the verdict.
void finish(const ChapterOptions& options, const Report& report,
            const std::vector<ch07::SceneResult>& results, const ch07::RunnerOptions& runner) {
  report.print(std::cout);
  std::cout << ch07::tracer_tables(results, to_string(MemoryPath::global), runner,
                                   describe_backend(runner.backend),
                                   ch07::course_anchors(std::cout));
  if (!options.common.json.empty()) report.write_json(options.common.json);
  for (const ch07::SceneResult& r : results)
    if (r.problems > 0)
      throw Error("a memory path changed the hits: they must be chapter 07's");
}

int run_benchmark_mode(const ChapterOptions& options, Backend backend) {
  const std::vector<std::string> scenes = options.benchmark_scenes.empty()
                                              ? ch07::benchmark_set(options.models_dir)
                                              : options.benchmark_scenes;
  const ch07::RunnerOptions runner = runner_options(
      options, backend, options.size_given ? options.common.extent() : Extent{1920, 1080});
  Report report("Chapter 08: memory paths on the benchmark protocol", "Mrays/s",
                "chapter 07's hits, bit for bit");
  add_context(report, runner, options.paths);
  const std::vector<ch07::SceneResult> results =
      ch07::run_benchmark(scenes, {memory_path_tracers(options.paths, true)}, runner, report);
  finish(options, report, results, runner);
  return 0;
}

// The image: chapter 06's shading, smooth normals and shadows, through the kept path.
template <class Render>
void with_kept_scene(Backend backend, const ShadedScene& scene, const Bvh& bvh,
                     const PackedBvh& packed, Render render) {
  const unsigned features = ch06::features_used(scene, true, true);
  if (backend == Backend::gpu) {
    const ch06::DeviceShadedScene d_scene(scene, features);
    const DeviceTrees trees(bvh, packed, false);
    render(features, ch07::with_bvh(d_scene.view(), trees.kept()));
  } else {
    render(features, ch07::with_bvh(ch06::host_view(scene, features), host_kept_view(packed)));
  }
}

void render_image(const ChapterOptions& options, Backend backend, const ShadedScene& scene,
                  const ch03::CameraSpec& spec) {
  const Bvh bvh = ch07::build_bvh(scene.mesh, {});
  const PackedBvh packed = pack_bvh(bvh);
  const Extent extent = options.common.extent();
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  const Image image = render_into_image(backend, extent, [&](Rgba8* pixels) {
    with_kept_scene(backend, scene, bvh, packed,
                    [&](unsigned features, const KeptSceneView& view) {
                      render_kept_shaded(backend, features, view, camera, extent, pixels);
                    });
  });
  write_image(options.common.output, image);
  std::cout << "wrote " << options.common.output << "\n";
}

void run_window(const ChapterOptions& options, Backend backend, ch02::Viewer& viewer,
                const ShadedScene& scene, const ch03::CameraSpec& start, Report& report) {
  const Bvh bvh = ch07::build_bvh(scene.mesh, {});
  const PackedBvh packed = pack_bvh(bvh);
  with_kept_scene(
      backend, scene, bvh, packed, [&](unsigned features, const KeptSceneView& view) {
        const ch03::WindowSettings window{"ch08: memory spaces", options.common.frames,
                                          "ch08_screenshot"};
        const ch03::WindowResult shown = ch03::run_window(
            viewer, backend, start, window,
            [&](Backend b, const ch03::CameraSpec& spec, Extent extent, Rgba8* pixels) {
              render_kept_shaded(b, features, view, ch03::make_camera<float>(spec, extent),
                                 extent, pixels);
            });
        if (shown.frames == 0) return;
        report.add_row(
            {"shaded frame, " + std::string(to_string(k_kept_path)) + ", window (" +
                 shown.path + ")",
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
      });
}

int run(ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  if (options.benchmark) return run_benchmark_mode(options, backend);

  ch03::CameraSpec camera = options.camera;
  const ShadedScene scene = ch06::load_framed_obj(options.scene_path, camera, options.eye_given,
                                                  options.target_given);
  ch03::validate_camera(camera);

  const std::unique_ptr<ch02::Viewer> viewer =
      ch03::open_viewer(options.display, options.common.extent(), "ch08: memory spaces");
  Report report("Chapter 08: memory spaces for the traversal", "Mrays/s",
                "chapter 07's hits bit for bit; float64 brute force (CPU) on sampled rays");
  if (viewer) {
    report.add_context("device", describe_backend(backend));
    report.add_context("mode", ch03::k_window_mode);
    run_window(options, backend, *viewer, scene, camera, report);
  } else {
    if (options.image_only) {
      if (options.common.output.empty()) throw UsageError("--image-only needs --output");
      render_image(options, backend, scene, camera);
      return 0;
    }
    ch07::RunnerOptions runner = runner_options(options, backend, options.common.extent());
    runner.reference_rays = options.reference_rays;
    add_context(report, runner, options.paths);
    report.add_context("scene",
                       options.scene_path + ", " +
                           group_digits(static_cast<long long>(scene.mesh.triangles.size())) +
                           " triangles");
    report.add_context("mode", ch03::k_headless_mode);
    std::vector<ch07::SceneResult> results;
    for (const Backend b : report_backends(backend, options.skip_cpu)) {
      runner.backend = b;
      const ch07::SceneResult result = ch07::run_scene(
          {options.scene_path}, {memory_path_tracers(options.paths, true)}, runner, report);
      if (results.empty())
        results.push_back(result);
      else
        results.front().problems += result.problems;
    }
    runner.backend = backend;
    finish(options, report, results, runner);
    if (!options.common.output.empty()) render_image(options, backend, scene, camera);
    return 0;
  }
  report.print(std::cout);
  if (!options.common.json.empty()) report.write_json(options.common.json);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 08: memory spaces for the traversal: plain, read-only, packed and "
               "texture loads, measured",
               "ch08_texture_memory"};
  ChapterOptions options;
  options.common.width = 1280;
  options.common.height = 720;
  options.common.output = "ch08_texture_memory.png";
  add_common_options(app, options.common);
  ch03::add_camera_options(app, options.camera);
  app.add_option("--scene", options.scene_path, "OBJ file to trace (.obj or gzip'd)")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--memory",
         [&](const std::string& text) {
           options.paths = parse_memory_paths(text);
           options.paths_given = true;
         },
         "Memory paths to measure, comma-separated: global, ldg, float4, float4_ldg, texture, "
         "or all (the CPU has global and float4)")
      ->default_str("all");
  app.add_option("--reference-rays", options.reference_rays,
                 "Rays per ray type the float64 reference traces (every triangle, in double)")
      ->check(CLI::Range(1LL, 1LL << 20))
      ->capture_default_str();
  app.add_flag("--skip-cpu", options.skip_cpu, "On the GPU, leave out the CPU rows");
  app.add_flag("--image-only", options.image_only,
               "Headless: write the --output image and skip the measurements");
  app.add_flag(
      "--benchmark", options.benchmark,
      "Every memory path on the SCENE files given, or on the benchmark set in --models");
  app.add_option("scenes", options.benchmark_scenes, "With --benchmark: OBJ files to measure")
      ->check(CLI::ExistingFile);
  app.add_option("--models", options.models_dir, "Where --benchmark finds the benchmark set")
      ->capture_default_str();
  ch03::add_display_options(app, options.display);
  return run_main(app, argc, argv, [&] {
    options.eye_given = app.get_option("--eye")->count() > 0;
    options.target_given = app.get_option("--target")->count() > 0;
    options.size_given =
        app.get_option("--width")->count() > 0 || app.get_option("--height")->count() > 0;
    if (!options.benchmark_scenes.empty() && !options.benchmark)
      throw UsageError("scene files on the command line go with --benchmark (else --scene)");
    if (!options.common.output.empty()) check_image_path(options.common.output);
    return run(options);
  });
}
