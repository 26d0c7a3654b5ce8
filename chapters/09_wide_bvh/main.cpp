// Chapter 09: wide trees for incoherent rays. By default it loads the course's ~100k-triangle
// model (or any OBJ file with --scene), traces the benchmark protocol's primary, ambient
// occlusion and diffuse rays through the binary tree (chapter 08's kept path) and each wide
// tree of this chapter, each checked against chapter 07's hits, and renders the shaded image
// through the compressed tree. Other modes:
//   --window                       the interactive viewer, shaded through the compressed tree
//   --rays FILE --hits FILE        a ray file through --tracer, hits to a file
//   --dump-hits FILE --ray-type T  the protocol's hits of one view through --tracer
//   --benchmark [SCENE...]         every tracer on the benchmark set (default) or the scenes
//   --heat-map                     the image shows the wide nodes each camera ray visits
// --split sbvh builds every tree, the binary one included, with chapter 07's spatial splits.
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "bvh_build.h"
#include "camera_cli.h"
#include "heat_map.h"
#include "program.h"
#include "query_modes.h"
#include "rt/image.h"
#include "rt/program_output.h"
#include "runner.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "wide_render.h"
#include "wide_trace.h"
#include "wide_tracers.h"

namespace {

using namespace rt;
using namespace rt::ch09;

struct ChapterOptions : ch03::ProgramOptions {
  ch07::QueryOptions query;
  ch07::BuildOptions
      build; // --split and --split-budget: the binary tree every tree starts from
  std::optional<ChapterTracer> tracer; // --tracer: the one traced (queries) or measured
  long long reference_rays = ch07::k_protocol_reference_rays;
  bool skip_cpu = false;
  bool heat_map = false; // the image shows wide nodes visited per ray instead of shading
};

// The chapter's flags that only some modes read (chapter 07's query_modes.h): the image is
// always traced through the compressed tree.
const ch07::FlagModes k_chapter_flags[] = {
    {"--tracer", ch07::k_traced_modes},
    {"--reference-rays", ch07::k_report_modes},
    {"--skip-cpu", ch07::k_report_modes},
    {"--heat-map", ch07::k_image_modes},
};

// The error of a run in which a tree broke its rule.
constexpr const char* k_disagreement =
    "a tree disagrees with chapter 07's hits beyond exact ties";

// The split of the binary trees, for the report's title and context.
std::string split_text(const ch07::BuildOptions& build) {
  if (build.method != ch07::SplitMethod::sbvh) return "sah";
  return "sbvh, references up to " + format_fixed(1.0 + build.split_budget, 2) +
         " times the triangles";
}

void add_split_context(Report& report, const ch07::BuildOptions& build) {
  report.add_context("wide trees",
                     "collapsed from binary trees built with " + split_text(build));
}

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

// One table per ray type (every tree against the binary one), and the trees' memory.
std::string tree_tables(const std::vector<ch07::SceneResult>& results,
                        const ch07::RunnerOptions& runner) {
  return ch07::tracer_tables(results, to_string(ChapterTracer::binary), runner,
                             describe_backend(runner.backend),
                             ch07::course_anchors(std::cout)) +
         memory_table(results);
}

// The tables of the first backend's figures, and the verdict on every backend's.
void print_tables(const std::vector<ch07::SceneResult>& results,
                  const ch07::RunnerOptions& runner, long long problems) {
  std::cout << tree_tables(results, runner);
  if (problems > 0) throw Error(k_disagreement);
}

// --benchmark: every tree (or --tracer and the binary one) on the protocol, each wide tree's
// build as a row.
ch07::BenchmarkMode benchmark_mode(const ChapterOptions& options, Backend backend) {
  ch07::BenchmarkMode mode;
  const bool spatial = options.build.method == ch07::SplitMethod::sbvh;
  mode.title = std::string("Chapter 09: wide trees on the benchmark protocol") +
               (spatial ? ", from spatial-split (sbvh) binary trees" : "");
  mode.reference = "chapter 07's hits up to exact ties; brute force on sampled rays";
  mode.runner.count_work = backend == Backend::cpu; // the CPU's work counters, on CPU runs only
  mode.runner.build.method = options.build.method;
  mode.runner.build.split_budget = options.build.split_budget;
  mode.context = [&options](Report& report) { add_split_context(report, options.build); };
  mode.tracers = [&options](Report& report) {
    return std::vector<ch07::TracerMaker>{
        chapter_tracers(measured(options), build_rows(report))};
  };
  mode.tables = tree_tables;
  mode.disagreement = k_disagreement;
  return mode;
}

int run(ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  if (options.query.benchmark)
    return ch07::run_benchmark_mode(benchmark_mode(options, backend), options.query, options,
                                    backend);
  if (options.query.query())
    return ch07::run_query(options.query, options, backend, options.build,
                           ch04::TriangleVariant::watertight,
                           chapter_tracers({options.tracer.value_or(ChapterTracer::cwbvh8)}));

  ch03::CameraSpec camera = options.camera;
  const ch06::ShadedScene scene =
      ch06::load_framed_obj(options.query.scene_path, camera, options.common.extent(),
                            options.eye_given, options.target_given);
  ch03::validate_camera(camera);
  const bool spatial = options.build.method == ch07::SplitMethod::sbvh;
  Report report = start_report(
      std::string("Chapter 09: a wide compressed tree for incoherent rays") +
          (spatial ? ", from a spatial-split (sbvh) binary tree" : ""),
      "Mrays/s",
      "chapter 07's hits up to exact ties; float64 brute force (CPU) on sampled rays", backend);

  // The image and the window: chapter 06's shading through the compressed tree.
  const unsigned features = ch06::features_used(scene, true, true);
  std::optional<CompressedBvh> tree; // built for the first frame
  std::optional<ch06::DeviceShadedScene> d_scene;
  std::optional<DeviceWideTree<CompressedNode>> d_tree; // uploaded for the first GPU frame
  ch07::RunnerOptions runner;
  runner.extent = options.common.extent();
  runner.backend = backend;
  runner.build = options.build;
  runner.frames = options.common.frames;
  runner.reference_rays = options.reference_rays;
  runner.count_work = true; // run_scene_on_each counts on its CPU run alone
  ch07::BackendRuns runs;
  const ch03::ProgramParts parts{
      .chapter = "ch09",
      .window_title = "wide compressed tree",
      .camera = camera,
      .render_with_radiance =
          [&](Backend b, const ch03::CameraSpec& spec, Extent extent, Rgba8* pixels,
              Vec3f* radiance) {
            if (!tree)
              tree.emplace(
                  compress(build_wide_layout(scene.mesh, 8, Collapse::sah, options.build)));
            if (b == Backend::gpu && !d_scene) {
              d_scene.emplace(scene, features);
              d_tree.emplace(*tree);
            }
            const CompressedSceneView view =
                d_scene ? with_wide(d_scene->view(), d_tree->view())
                        : with_wide(ch06::host_view(scene, features), tree->view());
            if (options.heat_map)
              return render_wide_heat_map(
                  b, view.mesh.tree, ch03::make_camera<float>(spec, extent), extent, pixels);
            render_wide_shaded(b, features, view, ch03::make_camera<float>(spec, extent),
                               extent, pixels, nullptr, radiance);
          },
      .window_row =
          [&](const ch03::WindowResult& shown) {
            return ch03::window_fps_row("shaded frame, cwbvh8", backend, shown);
          },
      .measure =
          [&](Report& rows) {
            ch07::add_runner_context(rows, runner);
            add_split_context(rows, options.build);
            rows.add_context("scene", options.query.scene_path + ", " +
                                          group_digits(std::ssize(scene.mesh.triangles)) +
                                          " triangles");
            runs = ch07::run_scene_on_each(
                report_backends(backend, options.skip_cpu), {options.query.scene_path},
                {chapter_tracers(measured(options), build_rows(rows))}, runner, rows);
          },
  };
  const int code = ch03::run_window_or_headless(options, backend, parts, report);
  if (!runs.first.empty()) print_tables(runs.first, runner, runs.problems);
  return code;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 09: a wide compressed tree (8 children, 80-byte nodes) for incoherent "
               "rays, against chapter 07's binary tree",
               "ch09_wide_bvh"};
  ChapterOptions options;
  ch07::set_tree_program_defaults(options, options.query, "ch09_wide_bvh.png", RT_ASSETS_DIR,
                                  RT_MODELS_DIR);
  ch03::add_program_options(app, options);
  ch07::add_query_options(app, options.query, "every tree's rays, build and memory");
  app.add_option_function<std::string>(
         "--tracer", [&](const std::string& text) { options.tracer = parse_tracer(text); },
         "One tracer: binary, wide4, wide8, cwbvh8, cwbvh8_greedy, wide4_packed, "
         "wide4_packed_shared_stack, wide4_packed_persistent, wide4_packed_sorted, "
         "wide4_packed_tiles, wide4_packed_persistent_tiles or cpu8 (the "
         "CPU's own tree, CPU backend only) (the queries' tree; the measurements then compare "
         "it with binary alone)")
      ->default_str("all (queries: cwbvh8)");
  ch07::add_reference_options(app, options.reference_rays, options.skip_cpu);
  // Chapter 07's --split and --split-budget, less its median split: the collapse chooses the
  // leaves itself (binary_options), so --leaf-size would do nothing here.
  app.add_option_function<std::string>(
         "--split",
         [&](const std::string& text) {
           options.build.method =
               text == "sbvh" ? ch07::SplitMethod::sbvh : ch07::SplitMethod::sah;
         },
         "The binary tree every tree is built from, the wide ones collapsed from it: sah, or "
         "sbvh (chapter 07's spatial splits: a triangle may be in several leaves)")
      ->check(CLI::IsMember({"sah", "sbvh"}))
      ->default_str("sah");
  ch07::add_split_budget_option(app, options.build);
  app.add_flag("--heat-map", options.heat_map,
               "The image shows how many wide nodes each pixel's ray visits (chapter 07's "
               "colours: white at " +
                   std::to_string(ch07::k_heat_map_max_nodes) + " or more)");
  ch03::add_image_only_option(app, options);
  return ch03::run_program_main(app, argc, argv, options, [&] {
    ch07::check_query_options(options.query, options, app, k_chapter_flags);
    ch07::check_split_budget(options.build, app);
    if (options.heat_map && is_linear_image_path(options.common.output))
      throw UsageError("--heat-map draws node counts, not radiance: write it as a .png");
    return run(options);
  });
}
