// Chapter 07: the bounding volume hierarchy. By default it loads a ~100k-triangle model (the
// course's torus knot, or any OBJ file with --scene), builds the tree by median split and by
// SAH, and traces the camera's rays through each against brute force and a float64 reference,
// then renders chapter 06's shading through the tree. Other modes:
//   --window                       the interactive viewer, shaded through the tree
//   --rays FILE --hits FILE        any batch of rays from a file, hits to a file
//   --dump-hits FILE --ray-type T  the benchmark protocol's rays for one view, hits to a file
//   --benchmark [SCENE...]         the benchmark protocol (default: the benchmark set)
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "bvh_build.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "camera_cli.h"
#include "chapter_report.h"
#include "heat_map.h"
#include "program.h"
#include "query_modes.h"
#include "rt/program_output.h"
#include "runner.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "variant_cli.h"

namespace {

using namespace rt;
using namespace rt::ch07;
using ch06::ShadedScene;

struct ChapterOptions : ch03::ProgramOptions {
  QueryOptions query;
  BuildOptions build;
  TriangleVariant variant = TriangleVariant::watertight;
  bool smooth = true, shadows = true;
  long long reference_pixels = k_protocol_reference_rays; // rays the float64 reference traces
  bool skip_cpu = false;
  bool end_to_end = true;                 // with --benchmark: also the shaded frame
  int check_rays = k_protocol_check_rays; // with --benchmark: rays per ray type checked
  bool heat_map = false; // the image shows nodes visited per ray instead of shading
};

// The chapter's flags that only some modes read (query_modes.h); given in another mode, they
// are refused. The image is always shaded through the watertight test.
const FlagModes k_chapter_flags[] = {
    {"--variant", k_traced_modes},
    {"--shading", k_image_modes},
    {"--shadows", k_image_modes},
    {"--heat-map", k_image_modes},
    {"--reference-pixels", k_report_modes},
    {"--skip-cpu", k_report_modes},
    {"--end-to-end", {ProgramMode::benchmark}},
    {"--check-rays", {ProgramMode::benchmark}},
};

// Flags that do nothing beside another of the chapter's: the median split has no bins (the
// report alone builds a SAH tree as well), only spatial splits spend a budget, and the heat map
// is not shaded.
void check_chapter_flags(const ChapterOptions& options, const CLI::App& app) {
  const ProgramMode mode = program_mode(options.query, options);
  if (options.build.method == SplitMethod::median && app.count("--bins") > 0 &&
      mode != ProgramMode::report)
    throw UsageError("--bins does nothing with --split median, which cuts at the median "
                     "without bins");
  check_split_budget(options.build, app);
  for (const char* flag : {"--shading", "--shadows"})
    if (options.heat_map && app.count(flag) > 0 && mode != ProgramMode::report)
      throw UsageError(std::string(flag) +
                       " does nothing with --heat-map, whose image counts nodes");
}

// --benchmark: the tree of --split on the protocol, its build and the shaded frame, and the
// summary table the book prints.
BenchmarkMode benchmark_mode(const ChapterOptions& options) {
  BenchmarkMode mode;
  mode.title = "Chapter 07: benchmark protocol";
  mode.reference = "chapter 07's hits; brute force on sampled rays";
  mode.runner.variant = options.variant;
  mode.runner.build = options.build;
  mode.runner.check_rays = options.check_rays;
  mode.runner.build_rows = true;
  mode.runner.end_to_end = options.end_to_end;
  mode.tracers = [](Report&) { return std::vector<TracerMaker>{chapter07_tracers}; };
  mode.tables = [](const std::vector<SceneResult>& results, const RunnerOptions& runner) {
    return "\n" + summary_table(results, to_string(runner.build.method),
                                describe_backend(runner.backend), course_anchors(std::cout));
  };
  mode.disagreement = "the tree disagrees with brute force on sampled rays";
  return mode;
}

int run(ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  check_build_options(options.build);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  if (options.query.benchmark)
    return run_benchmark_mode(benchmark_mode(options), options.query, options, backend);
  if (options.query.query())
    return run_query(options.query, options, backend, options.build, options.variant,
                     chapter07_tracers);

  ch03::CameraSpec camera = options.camera;
  const ShadedScene scene =
      ch06::load_framed_obj(options.query.scene_path, camera, options.common.extent(),
                            options.eye_given, options.target_given);
  ch03::validate_camera(camera);
  Report report = start_report("Chapter 07: bounding volume hierarchy", "Mrays/s",
                               "float64 brute force (CPU, sampled rays)", backend);
  report.add_context("image", to_string(options.common.extent()));
  report.add_context("scene", options.query.scene_path + ", " +
                                  group_digits(std::ssize(scene.mesh.triangles)) +
                                  " triangles");
  report.add_context("tree", "leaves of up to " + std::to_string(options.build.max_leaf_size) +
                                 " triangles, " + std::to_string(options.build.bins) +
                                 " SAH bins; triangle test " +
                                 ch04::to_string(options.variant));
  report.add_context("error column",
                     "triangle ids differing from the float64 reference on " +
                         group_digits(options.reference_pixels) +
                         " sampled rays, worst relative t error; hits against the SAH tree's; "
                         "work per ray");

  const unsigned features = ch06::features_used(scene, options.smooth, options.shadows);
  std::optional<Bvh> bvh;                         // built for the first frame
  std::optional<ch06::DeviceShadedScene> d_scene; // uploaded for the first GPU frame
  std::optional<DeviceBvh> d_bvh;
  const ch03::ProgramParts parts{
      .chapter = "ch07",
      .window_title = "bounding volume hierarchy",
      .camera = camera,
      .render_with_radiance =
          [&](Backend b, const ch03::CameraSpec& spec, Extent extent, Rgba8* pixels,
              Vec3f* radiance) {
            if (!bvh) bvh.emplace(build_bvh(scene.mesh, options.build));
            if (b == Backend::gpu && !d_scene) {
              d_scene.emplace(scene, features);
              d_bvh.emplace(*bvh);
            }
            const BvhSceneView view =
                d_scene ? with_bvh(d_scene->view(), d_bvh->view())
                        : with_bvh(ch06::host_view(scene, features), bvh->view());
            const auto frame_camera = ch03::make_camera<float>(spec, extent);
            if (options.heat_map)
              return render_node_heat_map(b, view.mesh.bvh, frame_camera, extent, pixels);
            render_bvh_shaded(b, features, view, frame_camera, extent, pixels, nullptr,
                              radiance);
          },
      .window_row =
          [&](const ch03::WindowResult& shown) {
            return ch03::window_fps_row("shaded frame, BVH (SAH)", backend, shown);
          },
      .measure =
          [&](Report& rows) {
            const ChapterReportOptions chapter{
                options.query.scene_path, options.common.extent(), options.build,
                options.variant,          options.smooth,          options.shadows,
                options.reference_pixels, options.common.frames};
            report_chapter(chapter, report_backends(backend, options.skip_cpu), scene,
                           ch03::make_camera<float>(camera, options.common.extent()), rows);
          },
  };
  return ch03::run_window_or_headless(options, backend, parts, report);
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 07: the bounding volume hierarchy: build, traversal, benchmark",
               "ch07_bvh"};
  ChapterOptions options;
  set_tree_program_defaults(options, options.query, "ch07_bvh.png", RT_ASSETS_DIR,
                            RT_MODELS_DIR);
  ch03::add_program_options(app, options);
  ch04::add_triangle_variant_option(app, options.variant);
  app.get_option("--variant")
      ->description("Triangle test of the measurements, the queries and the benchmark (the "
                    "image always uses the watertight test)");
  add_query_options(app, options.query, "the tree's rays, build and shaded frame");
  add_build_options(app, options.build);
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
  ch03::add_image_only_option(app, options);
  app.add_flag("--heat-map", options.heat_map,
               "The image shows how many nodes each camera ray visits (black: none, white: 48 "
               "or more) instead of the shaded frame");
  add_on_off_option(app, "--end-to-end", options.end_to_end,
                    "With --benchmark: also time the shaded frame");
  app.add_option("--check-rays", options.check_rays,
                 "With --benchmark: rays per ray type checked against brute force (as many as "
                 "the image has: every ray)")
      ->check(CLI::Range(0, rt::k_max_image_side * rt::k_max_image_side))
      ->capture_default_str();
  return ch03::run_program_main(app, argc, argv, options, [&] {
    check_query_options(options.query, options, app, k_chapter_flags);
    check_chapter_flags(options, app);
    if (options.heat_map && is_linear_image_path(options.common.output))
      throw UsageError("--heat-map draws node counts, not radiance: write it as a .png");
    return run(options);
  });
}
