// Chapter 09: a wide compressed tree for incoherent rays. By default it loads the course's
// ~100k-triangle model (or any OBJ file with --scene), traces the benchmark protocol's primary,
// ambient occlusion and diffuse rays through the binary tree (chapter 08's kept path) and each
// wide tree of this chapter, each checked against chapter 07's hits, and renders the shaded
// image through the compressed tree. Other modes:
//   --window                       the interactive viewer, shaded through the compressed tree
//   --rays FILE --hits FILE        any batch of rays from a file through --tracer, hits to a
//   file
//   --dump-hits FILE --ray-type T  the protocol's rays for one view through --tracer
//   --benchmark [SCENE...]         every tracer on the benchmark set (default) or the scenes
//   given
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bvh_build.h"
#include "camera_cli.h"
#include "obj_loader.h"
#include "protocol.h"
#include "ray_io.h"
#include "rt/backend_image.h"
#include "rt/cli.h"
#include "rt/report.h"
#include "runner.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "viewer.h"
#include "wide_render.h"
#include "wide_trace.h"
#include "wide_tracers.h"
#include "window_loop.h"

namespace {

using namespace rt;
using namespace rt::ch09;
using ch07::RayType;

struct ChapterOptions {
  CommonOptions common;
  ch03::CameraSpec camera;
  bool eye_given = false, target_given = false, fov_given = false, size_given = false;
  std::string scene_path = RT_ASSETS_DIR "/torus_knot_100k.obj.gz";
  std::optional<ChapterTracer> tracer; // --tracer: the one traced (queries) or measured
  long long reference_rays = 1024;
  bool skip_cpu = false;
  bool image_only = false;
  ch03::DisplayChoice display;
  std::string rays_path, hits_path, dump_hits_path;
  RayType ray_type = RayType::primary;
  bool benchmark = false;
  std::vector<std::string> benchmark_scenes;
  std::string models_dir = RT_MODELS_DIR;
};

// The tracers measured: the binary tree and --tracer, or every one.
std::vector<ChapterTracer> measured(const ChapterOptions& options) {
  if (!options.tracer || *options.tracer == ChapterTracer::binary)
    return {std::begin(k_all_tracers), std::end(k_all_tracers)};
  return {ChapterTracer::binary, *options.tracer};
}

// Each wide tree's build as a row of `report`.
BuildSink build_rows(Report& report) {
  return [&report](const std::string& scene, const std::string& tracer, const WideStats& s) {
    report.add_row(build_row(scene, tracer, s));
  };
}

ch07::RunnerOptions runner_options(const ChapterOptions& options, Backend backend,
                                   Extent extent) {
  ch07::RunnerOptions runner;
  runner.extent = extent;
  runner.backend = backend;
  runner.frames = options.common.frames;
  runner.count_work = backend == Backend::cpu;
  return runner;
}

void finish(const ChapterOptions& options, const Report& report,
            const std::vector<ch07::SceneResult>& results, const ch07::RunnerOptions& runner) {
  report.print(std::cout);
  std::cout << ch07::tracer_tables(results, to_string(ChapterTracer::binary), runner,
                                   describe_backend(runner.backend),
                                   ch07::course_anchors(std::cout))
            << memory_table(results);
  if (!options.common.json.empty()) report.write_json(options.common.json);
  for (const ch07::SceneResult& r : results)
    if (r.problems > 0)
      throw Error("a tree disagrees with chapter 07's hits beyond exact ties");
}

int run_benchmark_mode(const ChapterOptions& options, Backend backend) {
  const std::vector<std::string> scenes = options.benchmark_scenes.empty()
                                              ? ch07::benchmark_set(options.models_dir)
                                              : options.benchmark_scenes;
  ch07::RunnerOptions runner = runner_options(
      options, backend, options.size_given ? options.common.extent() : Extent{1920, 1080});
  runner.check_rays = 4096;
  Report report("Chapter 09: wide trees on the benchmark protocol", "Mrays/s",
                "chapter 07's hits up to exact ties; brute force on sampled rays");
  ch07::add_runner_context(report, runner);
  const std::vector<ch07::SceneResult> results = ch07::run_benchmark(
      scenes, {chapter_tracers(measured(options), build_rows(report))}, runner, report);
  finish(options, report, results, runner);
  return 0;
}

// --rays FILE --hits FILE, or --dump-hits FILE --ray-type T: through one tracer.
int run_query(const ChapterOptions& options, Backend backend) {
  const ch05::ObjMesh obj = ch05::load_obj(options.scene_path);
  const ch07::Bvh bvh = ch07::build_bvh(obj.geometry, {});
  const SingleTracer tracer(options.tracer.value_or(ChapterTracer::cwbvh8), backend,
                            obj.geometry, bvh);
  if (!options.rays_path.empty()) {
    if (options.hits_path.empty()) throw UsageError("--rays needs --hits FILE for the results");
    const std::vector<RayF> rays = ch07::read_ray_file(options.rays_path);
    ch07::write_hit_file(options.hits_path, tracer.trace(Query::closest, rays));
    std::cout << "traced " << group_digits(static_cast<long long>(rays.size()))
              << " rays through " << tracer.name() << " on " << describe_backend(backend)
              << "; wrote " << options.hits_path << "\n";
    return 0;
  }
  ch07::ProtocolView view = ch07::protocol_view(options.scene_path, bvh.bounds);
  if (options.eye_given) view.eye = options.camera.eye.as<float>();
  if (options.target_given) view.target = options.camera.target.as<float>();
  if (options.fov_given) view.vfov_degrees = static_cast<float>(options.camera.fov_degrees);
  const Extent extent = options.size_given ? options.common.extent() : Extent{1920, 1080};
  const ch07::PinholeCamera camera =
      ch07::make_protocol_camera(view, extent.width, extent.height);
  std::vector<MeshHit> hits = tracer.trace(Query::closest, ch07::camera_rays_cpu(camera));
  if (options.ray_type != RayType::primary) {
    const ch07::SecondaryRays secondary = ch07::secondary_rays_cpu(
        options.ray_type, obj.geometry, hits, camera, ch07::scene_radius(bvh.bounds));
    const Query query = options.ray_type == RayType::ao ? Query::any : Query::closest;
    hits = ch07::scatter_to_pixels(tracer.trace(query, secondary.rays), secondary.pixel,
                                   int(extent.pixel_count()));
  }
  ch07::write_hit_file(options.dump_hits_path, hits);
  std::cout << "wrote " << options.dump_hits_path << ": " << ch07::to_string(options.ray_type)
            << " hits through " << tracer.name() << ", " << extent.width << "x" << extent.height
            << "\n";
  return 0;
}

// The shaded scene through the compressed tree, on the backend's memory: render(features,
// view).
template <class Render>
void with_wide_scene(Backend backend, const ch06::ShadedScene& scene, Render render) {
  const CompressedBvh tree = compress(build_wide_layout(scene.mesh, 8, Collapse::sah));
  const unsigned features = ch06::features_used(scene, true, true);
  if (backend == Backend::gpu) {
    const ch06::DeviceShadedScene d_scene(scene, features);
    const DeviceWideTree<CompressedNode> d_tree(tree);
    render(features, with_wide(d_scene.view(), d_tree.view()));
  } else {
    render(features, with_wide(ch06::host_view(scene, features), tree.view()));
  }
}

void render_image(const ChapterOptions& options, Backend backend,
                  const ch06::ShadedScene& scene, const ch03::CameraSpec& spec) {
  const Extent extent = options.common.extent();
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  const Image image = render_into_image(backend, extent, [&](Rgba8* pixels) {
    with_wide_scene(backend, scene, [&](unsigned features, const CompressedSceneView& view) {
      render_wide_shaded(backend, features, view, camera, extent, pixels);
    });
  });
  write_image(options.common.output, image);
  std::cout << "wrote " << options.common.output << "\n";
}

void run_window(const ChapterOptions& options, Backend backend, ch02::Viewer& viewer,
                const ch06::ShadedScene& scene, const ch03::CameraSpec& start) {
  with_wide_scene(backend, scene, [&](unsigned features, const CompressedSceneView& view) {
    const ch03::WindowSettings window{"ch09: wide compressed tree", options.common.frames,
                                      "ch09_screenshot"};
    const ch03::WindowResult shown = ch03::run_window(
        viewer, backend, start, window,
        [&](Backend b, const ch03::CameraSpec& spec, Extent extent, Rgba8* pixels) {
          render_wide_shaded(b, features, view, ch03::make_camera<float>(spec, extent), extent,
                             pixels);
        });
    if (shown.frames == 0) return;
    std::cout << format_fixed(1000.0 / shown.frame_time.median_ms, 1)
              << " frames/s on screen through cwbvh8 (" << shown.path << ")\n";
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
  if (!options.rays_path.empty() || !options.dump_hits_path.empty())
    return run_query(options, backend);

  ch03::CameraSpec camera = options.camera;
  const ch06::ShadedScene scene = ch06::load_framed_obj(
      options.scene_path, camera, options.eye_given, options.target_given);
  ch03::validate_camera(camera);
  const std::unique_ptr<ch02::Viewer> viewer =
      ch03::open_viewer(options.display, options.common.extent(), "ch09: wide compressed tree");
  if (viewer) {
    run_window(options, backend, *viewer, scene, camera);
    return 0;
  }
  if (options.image_only) {
    if (options.common.output.empty()) throw UsageError("--image-only needs --output");
    render_image(options, backend, scene, camera);
    return 0;
  }
  Report report(
      "Chapter 09: a wide compressed tree for incoherent rays", "Mrays/s",
      "chapter 07's hits up to exact ties; float64 brute force (CPU) on sampled rays");
  ch07::RunnerOptions runner = runner_options(options, backend, options.common.extent());
  runner.reference_rays = options.reference_rays;
  ch07::add_runner_context(report, runner);
  report.add_context("scene",
                     options.scene_path + ", " +
                         group_digits(static_cast<long long>(scene.mesh.triangles.size())) +
                         " triangles");
  std::vector<ch07::SceneResult> results;
  for (const Backend b : report_backends(backend, options.skip_cpu)) {
    runner.backend = b;
    runner.count_work = b == Backend::cpu;
    results.push_back(ch07::run_scene({options.scene_path},
                                      {chapter_tracers(measured(options), build_rows(report))},
                                      runner, report));
  }
  runner.backend = backend;
  for (std::size_t k = 1; k < results.size(); ++k)
    results.front().problems += results[k].problems;
  results.resize(1); // the tables show the first backend's figures
  finish(options, report, results, runner);
  if (!options.common.output.empty()) render_image(options, backend, scene, camera);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 09: a wide compressed tree (8 children, 80-byte nodes) for incoherent "
               "rays, against chapter 07's binary tree",
               "ch09_wide_bvh"};
  ChapterOptions options;
  options.common.width = 1280;
  options.common.height = 720;
  options.common.output = "ch09_wide_bvh.png";
  add_common_options(app, options.common);
  ch03::add_camera_options(app, options.camera);
  app.add_option("--scene", options.scene_path, "OBJ file to trace (.obj or gzip'd)")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--tracer", [&](const std::string& text) { options.tracer = parse_tracer(text); },
         "One tracer: binary, wide4, wide8, cwbvh8 or cwbvh8_greedy (the queries' tree; the "
         "measurements then compare it with binary alone)")
      ->default_str("all (queries: cwbvh8)");
  app.add_option("--reference-rays", options.reference_rays,
                 "Rays per ray type the float64 reference traces (every triangle, in double)")
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
               "Every tracer on the SCENE files given, or on the benchmark set in --models");
  app.add_option("scenes", options.benchmark_scenes, "With --benchmark: OBJ files to measure")
      ->check(CLI::ExistingFile);
  app.add_option("--models", options.models_dir, "Where --benchmark finds the benchmark set")
      ->capture_default_str();
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
