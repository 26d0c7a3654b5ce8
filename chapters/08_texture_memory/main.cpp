// Chapter 08: memory spaces for the traversal. By default it loads the course's ~100k-triangle
// model (or any OBJ file with --scene), builds chapter 07's tree, and traces the benchmark
// protocol's primary, ambient occlusion and diffuse rays through every memory path (plain
// loads, read-only loads, 16-byte records, texture objects), each timed, each checked bit for
// bit against chapter 07's hits and on a sample against a float64 reference; then it renders
// the shaded image through the kept path. Other modes:
//   --window                       the interactive viewer, shaded through the kept path
//   --benchmark [SCENE...]         every path on the benchmark set (default) or the scenes
//   given
//   --rays FILE --hits FILE        a ray file through the first path of --memory
//   --dump-hits FILE --ray-type T  the protocol's hits of one view through that path
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "bvh_build.h"
#include "camera_cli.h"
#include "kept_render.h"
#include "memory_tracers.h"
#include "program.h"
#include "query_modes.h"
#include "rt/program_output.h"
#include "runner.h"
#include "shaded_render.h"
#include "shaded_scene.h"

namespace {

using namespace rt;
using namespace rt::ch08;
using ch06::ShadedScene;

struct ChapterOptions : ch03::ProgramOptions {
  ch07::QueryOptions query;
  std::vector<MemoryPath> paths{std::begin(k_all_paths), std::end(k_all_paths)};
  bool paths_given = false;
  long long reference_rays = ch07::k_protocol_reference_rays;
  bool skip_cpu = false;
};

// The chapter's flags that only some modes read (chapter 07's query_modes.h): the image is
// always traced through the kept path.
const ch07::FlagModes k_chapter_flags[] = {
    {"--memory", ch07::k_traced_modes},
    {"--reference-rays", ch07::k_report_modes},
    {"--skip-cpu", ch07::k_report_modes},
};

ch07::RunnerOptions runner_options(const ChapterOptions& options, Backend backend,
                                   Extent extent) {
  ch07::RunnerOptions runner;
  runner.extent = extent;
  runner.backend = backend;
  runner.frames = options.common.frames;
  return runner;
}

// The error of a run in which a path's hits were not chapter 07's.
constexpr const char* k_changed_hits =
    "a memory path changed the hits: they must be chapter 07's";

// The memory paths' context lines.
void add_path_context(Report& report, const std::vector<MemoryPath>& paths) {
  std::string described;
  for (const MemoryPath p : paths)
    described += std::string(described.empty() ? "" : "; ") + to_string(p) + ": " + describe(p);
  report.add_context("memory paths", described);
  report.add_context("kept path", std::string(to_string(k_kept_path)) +
                                      " (what the image and later chapters use)");
}

// One table per ray type: every path against the plain loads.
std::string path_tables(const std::vector<ch07::SceneResult>& results,
                        const ch07::RunnerOptions& runner) {
  return ch07::tracer_tables(results, to_string(MemoryPath::global), runner,
                             describe_backend(runner.backend), ch07::course_anchors(std::cout));
}

// The tables of the first backend's figures, and the verdict on every backend's.
void print_tables(const std::vector<ch07::SceneResult>& results,
                  const ch07::RunnerOptions& runner, long long problems) {
  std::cout << path_tables(results, runner);
  if (problems > 0) throw Error(k_changed_hits);
}

// --benchmark: every path of --memory on the protocol, one table per ray type.
ch07::BenchmarkMode benchmark_mode(const ChapterOptions& options) {
  ch07::BenchmarkMode mode;
  mode.title = "Chapter 08: memory paths on the benchmark protocol";
  mode.reference = "chapter 07's hits, bit for bit; brute force on sampled rays";
  mode.tracers = [&options](Report&) {
    return std::vector<ch07::TracerMaker>{memory_path_tracers(options.paths, true)};
  };
  mode.context = [&options](Report& report) { add_path_context(report, options.paths); };
  mode.tables = path_tables;
  mode.disagreement = k_changed_hits;
  return mode;
}

int run(ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  // Paths named with --memory must exist where the run is (`all` takes what exists there).
  if (options.paths_given)
    for (const MemoryPath path : options.paths) check_runs_on(path, backend);
  if (options.query.benchmark)
    return ch07::run_benchmark_mode(benchmark_mode(options), options.query, options, backend);
  if (options.query.query())
    return ch07::run_query(options.query, options, backend, {},
                           ch04::TriangleVariant::watertight,
                           memory_path_tracers({options.paths.front()}, false));

  ch03::CameraSpec camera = options.camera;
  const ShadedScene scene =
      ch06::load_framed_obj(options.query.scene_path, camera, options.common.extent(),
                            options.eye_given, options.target_given);
  ch03::validate_camera(camera);
  Report report = start_report(
      "Chapter 08: memory spaces for the traversal", "Mrays/s",
      "chapter 07's hits bit for bit; float64 brute force (CPU) on sampled rays", backend);

  const unsigned features = ch06::features_used(scene, true, true);
  std::optional<ch07::Bvh> bvh; // built for the first frame
  std::optional<PackedBvh> packed;
  std::optional<ch06::DeviceShadedScene> d_scene;
  std::optional<DeviceTrees> d_trees; // uploaded for the first GPU frame
  ch07::RunnerOptions runner = runner_options(options, backend, options.common.extent());
  runner.reference_rays = options.reference_rays;
  ch07::BackendRuns runs;
  const ch03::ProgramParts parts{
      .chapter = "ch08",
      .window_title = "memory spaces",
      .camera = camera,
      // Chapter 06's shading, smooth normals and shadows, through the kept path.
      .render_with_radiance =
          [&](Backend b, const ch03::CameraSpec& spec, Extent extent, Rgba8* pixels,
              Vec3f* radiance) {
            if (!bvh) {
              bvh.emplace(ch07::build_bvh(scene.mesh, {}));
              packed.emplace(pack_bvh(*bvh));
            }
            if (b == Backend::gpu && !d_scene) {
              d_scene.emplace(scene, features);
              d_trees.emplace(*bvh, *packed, false);
            }
            const KeptSceneView view =
                d_scene
                    ? ch07::with_bvh(d_scene->view(), d_trees->kept())
                    : ch07::with_bvh(ch06::host_view(scene, features), host_kept_view(*packed));
            render_kept_shaded(b, features, view, ch03::make_camera<float>(spec, extent),
                               extent, pixels, nullptr, radiance);
          },
      .window_row =
          [&](const ch03::WindowResult& shown) {
            return ch03::window_fps_row("shaded frame, " + std::string(to_string(k_kept_path)),
                                        backend, shown);
          },
      .measure =
          [&](Report& rows) {
            ch07::add_runner_context(rows, runner);
            add_path_context(rows, options.paths);
            rows.add_context("scene", options.query.scene_path + ", " +
                                          group_digits(std::ssize(scene.mesh.triangles)) +
                                          " triangles");
            runs = ch07::run_scene_on_each(
                report_backends(backend, options.skip_cpu), {options.query.scene_path},
                {memory_path_tracers(options.paths, true)}, runner, rows);
          },
  };
  const int code = ch03::run_window_or_headless(options, backend, parts, report);
  if (!runs.first.empty()) print_tables(runs.first, runner, runs.problems);
  return code;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 08: memory spaces for the traversal: plain, read-only, packed and "
               "texture loads, measured",
               "ch08_texture_memory"};
  ChapterOptions options;
  ch07::set_tree_program_defaults(options, options.query, "ch08_texture_memory.png",
                                  RT_ASSETS_DIR, RT_MODELS_DIR);
  ch03::add_program_options(app, options);
  ch07::add_query_options(app, options.query, "every memory path's rays");
  app.add_option_function<std::string>(
         "--memory",
         [&](const std::string& text) {
           options.paths = parse_memory_paths(text);
           options.paths_given = true;
         },
         "Memory paths to measure, comma-separated: global, ldg, float4, float4_ldg, texture, "
         "or all (the CPU has global and float4); the first one answers --rays and "
         "--dump-hits")
      ->default_str("all");
  ch07::add_reference_options(app, options.reference_rays, options.skip_cpu);
  ch03::add_image_only_option(app, options);
  return ch03::run_program_main(app, argc, argv, options, [&] {
    ch07::check_query_options(options.query, options, app, k_chapter_flags);
    return run(options);
  });
}
