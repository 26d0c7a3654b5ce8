// Chapter 10: trees built on the GPU, and scenes that move. By default it loads the course's
// ~100k-triangle model (or any OBJ file with --scene), builds its tree with every builder
// (chapter 07's SAH on the CPU, the LBVH of 30- and 63-bit codes, PLOC, H-PLOC), reports each
// build and traces the benchmark protocol's rays through each tree, binary and 4-wide, and
// renders the shaded image through the LBVH. Other modes:
//   --moving --frames N [--update U]  the moving scene, its tree rebuilt or refitted each frame
//   --rays FILE --hits FILE           a ray file through --builder's tree, hits to a file
//   --dump-hits FILE --ray-type T     the protocol's hits of one view through --builder's tree
//   --benchmark [SCENE...]            every builder on the benchmark set (default) or the
//   scenes
// --collapse sah|depth picks how the parallel collapse chooses wide nodes (wide_collapse.h),
// in every mode but --image-only.
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "builders.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "camera_cli.h"
#include "moving_program.h"
#include "program.h"
#include "query_modes.h"
#include "rt/program_output.h"
#include "runner.h"
#include "shaded_render.h"
#include "shaded_scene.h"

namespace {

using namespace rt;
using namespace rt::ch10;

struct ChapterOptions : ch03::ProgramOptions {
  ch07::QueryOptions query;
  std::optional<Builder> builder;            // --builder: the one built (queries) or measured
  CollapseRule collapse = CollapseRule::sah; // --collapse: the parallel collapse's rule
  bool moving = false;                       // --moving
  bool moving_model = false;    // --moving with --scene: the model instead of the torus
  std::optional<Update> update; // --update: one of them; both by default
  MovingOptions animation;      // --detail, --animation-csv
  bool skip_cpu = false;
};

// The builders measured: CPU SAH and --builder, or every one.
std::vector<Builder> measured(const ChapterOptions& options) {
  if (!options.builder || *options.builder == Builder::cpu_sah)
    return {std::begin(k_all_builders), std::end(k_all_builders)};
  return {Builder::cpu_sah, *options.builder};
}

// Each build as a row of `report`, and kept for the table printed after it.
BuildSink keep_builds(Report& report, std::vector<std::pair<Builder, BuiltTree>>& builds) {
  return [&report, &builds](const std::string& scene, Builder builder, const BuiltTree& tree) {
    report.add_row(build_row(scene, builder, tree));
    builds.push_back({builder,
                      {ch07::Bvh{{}, {}, {}, {}, {}, tree.bvh.stats}, tree.backend, tree.note,
                       tree.collapse_ms, tree.collapse_depth_ms}});
  };
}

// The chapter's flags that only some modes read (chapter 07's query_modes.h), outside
// --moving: the image is always traced through the LBVH.
const ch07::FlagModes k_chapter_flags[] = {
    {"--builder", ch07::k_traced_modes},
    {"--collapse", ch07::k_traced_modes},
    {"--skip-cpu", ch07::k_report_modes},
};

// One table per ray type (every builder's tree against chapter 07's), and the builds.
std::string builder_tables(const std::vector<ch07::SceneResult>& results,
                           const ch07::RunnerOptions& runner,
                           const std::vector<std::pair<Builder, BuiltTree>>& builds) {
  return ch07::tracer_tables(results, to_string(Builder::cpu_sah), runner,
                             describe_backend(runner.backend),
                             ch07::course_anchors(std::cout)) +
         build_table(builds);
}

// --benchmark: every builder (or --builder and chapter 07's) on the protocol, each build as a
// row of the report and of the builds' table.
ch07::BenchmarkMode benchmark_mode(const ChapterOptions& options,
                                   std::vector<std::pair<Builder, BuiltTree>>& builds) {
  ch07::BenchmarkMode mode;
  mode.title = "Chapter 10: every builder's tree on the benchmark protocol";
  mode.reference = "chapter 07's hits up to exact ties; brute force on sampled rays";
  mode.tracers = [&options, &builds](Report& report) {
    return std::vector<ch07::TracerMaker>{
        builder_tracers(measured(options), keep_builds(report, builds), options.collapse)};
  };
  mode.tables = [&builds](const std::vector<ch07::SceneResult>& results,
                          const ch07::RunnerOptions& runner) {
    return builder_tables(results, runner, builds);
  };
  mode.disagreement = "a tree disagrees with chapter 07's hits beyond exact ties";
  return mode;
}

int run(ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  std::vector<std::pair<Builder, BuiltTree>> builds;
  if (options.query.benchmark)
    return ch07::run_benchmark_mode(benchmark_mode(options, builds), options.query, options,
                                    backend);
  if (options.moving) {
    options.animation.animation.builder = options.builder.value_or(Builder::lbvh);
    options.animation.animation.collapse = options.collapse;
    if (options.moving_model) { // --scene: that model waving in the torus's place
      options.animation.animation.model = std::make_shared<const ch04::Mesh>(
          fit_moving_model(ch05::load_obj(options.query.scene_path).geometry));
      options.animation.model_name =
          std::filesystem::path(options.query.scene_path).filename().string();
    }
    if (options.update) options.animation.animation.updates = {*options.update};
    return run_moving_program(options, options.animation, backend);
  }
  if (options.query.query())
    return ch07::run_query(
        options.query, options, backend, {}, ch04::TriangleVariant::watertight,
        builder_tracers({options.builder.value_or(Builder::lbvh)}, {}, options.collapse));

  ch03::CameraSpec camera = options.camera;
  const ch06::ShadedScene scene =
      ch06::load_framed_obj(options.query.scene_path, camera, options.common.extent(),
                            options.eye_given, options.target_given);
  ch03::validate_camera(camera);
  Report report = start_report(
      "Chapter 10: trees built on the GPU", "Mrays/s",
      "chapter 07's hits up to exact ties; float64 brute force (CPU) on sampled rays", backend);
  const unsigned features = ch06::features_used(scene, true, true);
  std::optional<ch07::Bvh> tree; // the image's: the LBVH, built for the first frame
  std::optional<ch06::DeviceShadedScene> d_scene;
  std::optional<ch07::DeviceBvh> d_tree;
  ch07::RunnerOptions runner;
  runner.extent = options.common.extent();
  runner.backend = backend;
  runner.frames = options.common.frames;
  runner.reference_rays = ch07::k_protocol_reference_rays;
  runner.count_work = true;
  ch07::BackendRuns runs;
  const ch03::ProgramParts parts{
      .chapter = "ch10",
      .window_title = "a tree built on the GPU",
      .camera = camera,
      .render_with_radiance =
          [&](Backend b, const ch03::CameraSpec& spec, Extent extent, Rgba8* pixels,
              Vec3f* radiance) {
            if (!tree) tree = build_tree(Builder::lbvh, b, scene.mesh).bvh;
            if (b == Backend::gpu && !d_scene) {
              d_scene.emplace(scene, features);
              d_tree.emplace(*tree);
            }
            const ch07::BvhSceneView view =
                d_scene ? ch07::with_bvh(d_scene->view(), d_tree->view())
                        : ch07::with_bvh(ch06::host_view(scene, features), tree->view());
            ch07::render_bvh_shaded(b, features, view, ch03::make_camera<float>(spec, extent),
                                    extent, pixels, nullptr, radiance);
          },
      .window_row =
          [&](const ch03::WindowResult& shown) {
            return ch03::window_fps_row("shaded frame, LBVH", backend, shown);
          },
      .measure =
          [&](Report& rows) {
            ch07::add_runner_context(rows, runner);
            runs = ch07::run_scene_on_each(
                report_backends(backend, options.skip_cpu), {options.query.scene_path},
                {builder_tracers(measured(options), keep_builds(rows, builds),
                                 options.collapse)},
                runner, rows);
          },
  };
  const int code = ch03::run_window_or_headless(options, backend, parts, report);
  if (!runs.first.empty()) std::cout << builder_tables(runs.first, runner, builds);
  if (runs.problems > 0)
    throw Error("a tree disagrees with chapter 07's hits beyond exact ties");
  return code;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Chapter 10: trees built on the GPU (LBVH, PLOC, H-PLOC) against chapter 07's SAH "
      "build, and a moving scene's tree rebuilt or refitted every frame",
      "ch10_gpu_build"};
  ChapterOptions options;
  ch07::set_tree_program_defaults(options, options.query, "ch10_gpu_build.png", RT_ASSETS_DIR,
                                  RT_MODELS_DIR);
  ch03::add_program_options(app, options);
  ch07::add_query_options(app, options.query, "every builder's build and rays");
  app.add_option_function<std::string>(
         "--builder", [&](const std::string& text) { options.builder = parse_builder(text); },
         "One builder: cpu_sah, lbvh, lbvh63, ploc, hploc or hploc_treelets (the queries' and "
         "the moving "
         "scene's tree; the measurements then compare it with cpu_sah alone)")
      ->default_str("all (queries and --moving: lbvh)");
  app.add_option_function<std::string>(
         "--collapse",
         [&](const std::string& text) { options.collapse = parse_collapse_rule(text); },
         "The parallel collapse to 4-wide, of the traced trees and the moving scene's: sah "
         "(chapter 09's choice of children by cost) or depth (a fixed rule, looking at no "
         "cost)")
      ->default_str("sah");
  app.add_flag("--moving", options.moving,
               "The moving scene: in the window, its tree updated for every frame drawn "
               "(--update, default rebuild); headless, --frames frames (default 60) with the "
               "tree rebuilt and refitted, each frame's figures printed; with --scene, that "
               "model waves in the torus's place");
  app.add_option_function<std::string>(
         "--update", [&](const std::string& text) { options.update = parse_update(text); },
         "With --moving: rebuild or refit (the tree every frame)")
      ->default_str("both");
  app.add_option("--detail", options.animation.animation.detail,
                 "With --moving: the torus's segments around (detail^2 triangles; at most " +
                     std::to_string(k_max_moving_detail) +
                     ", which keeps the scene within a model's 10 million)")
      ->check(CLI::Range(8, k_max_moving_detail))
      ->capture_default_str();
  app.add_option("--animation-csv", options.animation.csv_path,
                 "With --moving: write each frame's tree ms, frame ms and SAH cost here");
  app.add_flag("--skip-cpu", options.skip_cpu, "On the GPU, leave out the CPU rows");
  ch03::add_image_only_option(app, options);
  return ch03::run_program_main(app, argc, argv, options, [&] {
    // --moving reads --builder in the window too (the moving scene's tree).
    const std::span<const ch07::FlagModes> chapter_flags =
        options.moving ? std::span<const ch07::FlagModes>{} : k_chapter_flags;
    ch07::check_query_options(options.query, options, app, chapter_flags);
    const bool moving_flags =
        options.update || !options.animation.csv_path.empty() || app.count("--detail") > 0;
    if (moving_flags && !options.moving)
      throw UsageError("--update, --detail and --animation-csv go with --moving");
    if (options.moving && (options.query.benchmark || options.query.query()))
      throw UsageError("--moving runs alone: not with --benchmark, --rays or --dump-hits");
    if (options.moving && is_linear_image_path(options.common.output))
      throw UsageError("--moving writes its last frame as a picture: give --output a .png");
    options.moving_model = options.moving && app.count("--scene") > 0;
    if (options.moving_model && app.count("--detail") > 0)
      throw UsageError("--detail sizes the torus: not with --moving --scene, whose model "
                       "waves in its place");
    if (options.moving) check_moving_outputs(options.animation);
    return run(options);
  });
}
