// Chapter 07: the query flags. See query_modes.h.
#include "query_modes.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <iterator>

#include "bvh_build.h"
#include "obj_loader.h"
#include "ray_io.h"
#include "rt/cli.h"
#include "rt/error.h"
#include "rt/output_file.h"
#include "rt/program_output.h"
#include "rt/report.h"

namespace rt::ch07 {
namespace {

Query query_for(RayType type) { return type == RayType::ao ? Query::any : Query::closest; }

// The scene's tracer, made as the runner makes it: chapter 07's tree of the mesh, the camera.
struct QueryScene {
  ch05::ObjMesh obj;
  Bvh bvh;
  PinholeCamera camera;
  Tracer tracer;
};

// The view of --dump-hits: the protocol's for the scene, with the camera flags given on top.
ProtocolView query_view(const QueryOptions& q, const ch03::ProgramOptions& p,
                        const Aabb& bounds) {
  ProtocolView view = protocol_view(q.scene_path, bounds);
  if (p.eye_given || p.target_given || p.fov_given) {
    if (p.eye_given) view.eye = p.camera.eye.as<float>();
    if (p.target_given) view.target = p.camera.target.as<float>();
    if (p.fov_given) view.vfov_degrees = static_cast<float>(p.camera.fov_degrees);
    view.kind = ViewKind::custom;
  }
  return view;
}

int run_ray_file(const QueryOptions& q, Backend backend, const Tracer& tracer) {
  const std::vector<RayF> rays = read_ray_file(q.rays_path);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<MeshHit> hits = trace_with(tracer, backend, Query::closest, rays);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
  write_hit_file(q.hits_path, hits);
  const auto hit_count =
      std::count_if(hits.begin(), hits.end(), [](const MeshHit& h) { return h.triangle >= 0; });
  std::cout << "traced " << group_digits(static_cast<long long>(rays.size())) << " rays on "
            << describe_backend(backend) << " through " << tracer.name << ": "
            << group_digits(hit_count) << " hit, " << format_fixed(ms, 1)
            << " ms with the upload; wrote " << q.hits_path << "\n";
  return 0;
}

int run_dump_hits(const QueryOptions& q, Backend backend, const QueryScene& s,
                  const ProtocolView& view) {
  const PinholeCamera& camera = s.camera;
  const std::vector<RayF> rays = camera_rays_cpu(camera);
  std::vector<MeshHit> hits = trace_with(s.tracer, backend, Query::closest, rays);
  if (q.ray_type != RayType::primary) {
    const SecondaryRays secondary = secondary_rays_cpu(q.ray_type, s.obj.geometry, hits, camera,
                                                       scene_radius(s.bvh.bounds));
    const std::vector<MeshHit> secondary_hits =
        trace_with(s.tracer, backend, query_for(q.ray_type), secondary.rays);
    hits = scatter_to_pixels(secondary_hits, secondary.pixel, camera.width * camera.height);
  }
  write_hit_file(q.dump_hits_path, hits);
  std::cout << "wrote " << q.dump_hits_path << ": " << to_string(q.ray_type) << " hits, "
            << camera.width << "x" << camera.height << ", view " << to_string(view.kind)
            << " (eye " << view.eye.x << "," << view.eye.y << "," << view.eye.z << ", target "
            << view.target.x << "," << view.target.y << "," << view.target.z << ", fov "
            << view.vfov_degrees << "), through " << s.tracer.name << "\n";
  return 0;
}

// The flag that picks a mode, and what the mode does, for the refusals.
const char* mode_flag(ProgramMode mode) {
  switch (mode) {
  case ProgramMode::report:
    return "the report";
  case ProgramMode::window:
    return "--window";
  case ProgramMode::image_only:
    return "--image-only";
  case ProgramMode::rays:
    return "--rays";
  case ProgramMode::dump_hits:
    return "--dump-hits";
  case ProgramMode::benchmark:
    return "--benchmark";
  }
  return "?";
}

const char* mode_work(ProgramMode mode) {
  switch (mode) {
  case ProgramMode::report:
    return "measures the chapter's tracers and writes the image";
  case ProgramMode::window:
    return "shows the image on screen";
  case ProgramMode::image_only:
    return "writes the image and measures nothing";
  case ProgramMode::rays:
    return "traces the file's rays as they are and writes their hits";
  case ProgramMode::dump_hits:
    return "writes the hits of the protocol's pinhole camera (up 0,1,0; --eye, --target, "
           "--fov, --width and --height move it)";
  case ProgramMode::benchmark:
    return "measures the protocol's views of its SCENE files, or of the benchmark set in "
           "--models";
  }
  return "?";
}

// The flags every program with a tree has, and the modes that read them (--backend and
// --headless: all).
constexpr ModeSet k_not_rays{ProgramMode::report, ProgramMode::window, ProgramMode::image_only,
                             ProgramMode::dump_hits, ProgramMode::benchmark};
const FlagModes k_common_flags[] = {
    {"--window", {ProgramMode::window}},
    {"--image-only", {ProgramMode::image_only}},
    {"--scene",
     {ProgramMode::report, ProgramMode::window, ProgramMode::image_only, ProgramMode::rays,
      ProgramMode::dump_hits}},
    {"--models", {ProgramMode::benchmark}},
    {"--output", k_image_modes},
    {"--json", {ProgramMode::report, ProgramMode::window, ProgramMode::benchmark}},
    // --image-only renders once, but tools/window-test.sh gives the window's --frames to both.
    {"--frames",
     {ProgramMode::report, ProgramMode::window, ProgramMode::image_only,
      ProgramMode::benchmark}},
    {"--width", k_not_rays},
    {"--height", k_not_rays},
    {"--eye",
     {ProgramMode::report, ProgramMode::window, ProgramMode::image_only,
      ProgramMode::dump_hits}},
    {"--target",
     {ProgramMode::report, ProgramMode::window, ProgramMode::image_only,
      ProgramMode::dump_hits}},
    {"--fov",
     {ProgramMode::report, ProgramMode::window, ProgramMode::image_only,
      ProgramMode::dump_hits}},
    {"--up", k_image_modes},
    {"--camera", k_image_modes},
};

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

// Throws the refusal of `flag`, given in `mode`, which does not read it.
void refuse_flag(const std::string& flag, ProgramMode mode, ModeSet modes) {
  if (mode != ProgramMode::report)
    throw UsageError(flag + " does nothing with " + mode_flag(mode) + ", which " +
                     mode_work(mode));
  // Without a mode flag: the flag belongs to a mode not asked for.
  std::string wanted;
  for (const ProgramMode m : {ProgramMode::benchmark, ProgramMode::rays, ProgramMode::dump_hits,
                              ProgramMode::window, ProgramMode::image_only})
    if (modes.has(m)) wanted += std::string(wanted.empty() ? "" : " or ") + mode_flag(m);
  throw UsageError(flag + " goes with " + wanted);
}

// The benchmark's scenes: the SCENE files given, else those of the benchmark set in --models,
// and the names of the set that are missing there.
struct BenchmarkScenes {
  std::vector<std::string> paths;
  std::vector<std::string> missing;
};

BenchmarkScenes benchmark_scenes(const QueryOptions& q) {
  if (!q.benchmark_scenes.empty()) return {q.benchmark_scenes, {}};
  return {benchmark_set(q.models_dir), missing_from_benchmark_set(q.models_dir)};
}

} // namespace

void set_tree_program_defaults(ch03::ProgramOptions& program, QueryOptions& query,
                               const std::string& output, const std::string& assets_dir,
                               const std::string& models_dir) {
  program.common.width = 1280;
  program.common.height = 720;
  program.common.output = output;
  query.scene_path = assets_dir + "/torus_knot_100k.obj.gz";
  query.models_dir = models_dir;
}

void add_reference_options(CLI::App& app, long long& reference_rays, bool& skip_cpu) {
  app.add_option("--reference-rays", reference_rays,
                 "Rays per ray type the float64 reference traces (every triangle, in double)")
      ->check(CLI::Range(1LL, 1LL << 20))
      ->capture_default_str();
  app.add_flag("--skip-cpu", skip_cpu, "On the GPU, leave out the CPU rows");
}

void add_query_options(CLI::App& app, QueryOptions& q,
                       const std::string& what_benchmark_measures) {
  app.add_option("--scene", q.scene_path,
                 "OBJ file to trace (.obj or gzip'd; " + ch05::describe_load_limits() + ")")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  app.add_option("--rays", q.rays_path,
                 "Trace the rays of this file (per ray: origin xyz, direction xyz, tmin, tmax; "
                 "float32 little-endian; " +
                     describe_ray_file_limits() + ")");
  app.add_option("--hits", q.hits_path,
                 "With --rays: write the closest hit of each ray here (float32 t, int32 id)");
  app.add_option("--dump-hits", q.dump_hits_path,
                 "Write the benchmark protocol's per-pixel hits of --ray-type here");
  app.add_option_function<std::string>(
         "--ray-type",
         [&q](const std::string& text) {
           q.ray_type = text == "ao"        ? RayType::ao
                        : text == "diffuse" ? RayType::diffuse
                                            : RayType::primary;
           q.ray_type_given = true;
         },
         "Rays for --dump-hits: primary, ao or diffuse")
      ->check(CLI::IsMember({"primary", "ao", "diffuse"}))
      ->default_str("primary");
  app.add_flag("--benchmark", q.benchmark,
               "Run the benchmark protocol on the SCENE files given, or on the benchmark set "
               "in --models (the scenes found there, with a warning naming any missing): " +
                   what_benchmark_measures);
  app.add_option("scenes", q.benchmark_scenes, "With --benchmark: OBJ files to measure")
      ->check(CLI::ExistingFile);
  app.add_option("--models", q.models_dir,
                 "Where --benchmark finds the benchmark set (tools/get-models.sh fills it)")
      ->capture_default_str();
  add_help_paragraph(app, "Modes: the report (the default), --window, --image-only, --rays, "
                          "--dump-hits and --benchmark each read only the flags they use; a "
                          "flag the mode asked for would not use is refused, naming both.");
}

void add_build_options(CLI::App& app, BuildOptions& build) {
  app.add_option_function<std::string>(
         "--split",
         [&build](const std::string& text) {
           build.method = text == "median" ? SplitMethod::median
                          : text == "sbvh" ? SplitMethod::sbvh
                                           : SplitMethod::sah;
         },
         "How the tree is built for the image, the ray files and the benchmark (sbvh: the "
         "SAH with spatial splits)")
      ->check(CLI::IsMember({"median", "sah", "sbvh"}))
      ->default_str("sah");
  app.add_option("--leaf-size", build.max_leaf_size, "Most triangles in a leaf")
      ->check(CLI::Range(1, k_max_leaf_size))
      ->capture_default_str();
  app.add_option("--bins", build.bins, "SAH bins per axis")
      ->check(CLI::Range(2, 256))
      ->capture_default_str();
  add_split_budget_option(app, build);
}

void add_split_budget_option(CLI::App& app, BuildOptions& build) {
  app.add_option("--split-budget", build.split_budget,
                 "With --split sbvh: the references may grow to (1 + this) times the triangles")
      ->check(CLI::Range(0.0, k_max_split_budget))
      ->capture_default_str();
}

void check_split_budget(const BuildOptions& build, const CLI::App& app) {
  if (build.method != SplitMethod::sbvh && app.count("--split-budget") > 0)
    throw UsageError("--split-budget goes with --split sbvh: only spatial splits copy "
                     "references");
}

ProgramMode program_mode(const QueryOptions& q, const ch03::ProgramOptions& p) {
  if (q.benchmark) return ProgramMode::benchmark;
  if (!q.rays_path.empty()) return ProgramMode::rays;
  if (!q.dump_hits_path.empty()) return ProgramMode::dump_hits;
  if (p.display.window) return ProgramMode::window;
  if (p.image_only) return ProgramMode::image_only;
  return ProgramMode::report;
}

void check_query_options(const QueryOptions& q, const ch03::ProgramOptions& p,
                         const CLI::App& app, std::span<const FlagModes> chapter_flags) {
  if (!q.benchmark_scenes.empty() && !q.benchmark)
    throw UsageError("scene files on the command line go with --benchmark (else --scene)");
  if (!q.benchmark_scenes.empty() && app.count("--models") > 0)
    throw UsageError("--models does nothing with SCENE files: --benchmark measures the files "
                     "given, or else the benchmark set in --models");
  if (!q.hits_path.empty() && q.rays_path.empty())
    throw UsageError("--hits goes with --rays FILE");
  if (!q.rays_path.empty() && q.hits_path.empty())
    throw UsageError("--rays needs --hits FILE for the results");
  if (!q.rays_path.empty() && !q.dump_hits_path.empty())
    throw UsageError("--rays and --dump-hits are two different queries: give one");
  if (q.ray_type_given && q.dump_hits_path.empty())
    throw UsageError("--ray-type goes with --dump-hits FILE");
  if (q.benchmark && q.query())
    throw UsageError("--benchmark measures the benchmark's own rays: leave out --rays and "
                     "--dump-hits");
  const ProgramMode mode = program_mode(q, p);
  for (const std::span<const FlagModes> flags :
       {std::span<const FlagModes>(k_common_flags), chapter_flags})
    for (const FlagModes& f : flags)
      if (app.count(f.flag) > 0 && !f.modes.has(mode)) refuse_flag(f.flag, mode, f.modes);
  // Outputs that cannot be written are refused before the work, not after it.
  if (!q.hits_path.empty()) check_output_path(q.hits_path, "hits");
  if (!q.dump_hits_path.empty()) check_output_path(q.dump_hits_path, "hits");
}

int run_benchmark_mode(const BenchmarkMode& mode, const QueryOptions& query,
                       const ch03::ProgramOptions& program, Backend backend) {
  RunnerOptions runner = mode.runner;
  runner.extent = program.size_given() ? program.common.extent() : k_protocol_extent;
  runner.backend = backend;
  runner.frames = program.common.frames;
  Report report(mode.title, "Mrays/s", mode.reference);
  add_runner_context(report, runner);
  if (mode.context) mode.context(report);
  const BenchmarkScenes scenes = benchmark_scenes(query);
  if (query.benchmark_scenes.empty())
    report.add_context(
        "scenes", "the benchmark set in " + query.models_dir +
                      (scenes.missing.empty() ? "" : ", without " + joined(scenes.missing)));
  // A set with models missing is measured on the others: said at the start, not only in the
  // report at the end.
  if (!scenes.missing.empty())
    warn("--benchmark: " + query.models_dir + " holds " + std::to_string(scenes.paths.size()) +
         " of the benchmark set's " + std::to_string(std::size(k_benchmark_set)) +
         " scenes; measuring those, without " + joined(scenes.missing) +
         " (tools/get-models.sh fetches them)");
  const std::vector<SceneResult> results =
      run_benchmark(scenes.paths, mode.tracers(report), runner, report);
  finish_report(report, program.common);
  std::cout << mode.tables(results, runner);
  for (const SceneResult& r : results)
    if (r.problems > 0) throw Error(mode.disagreement);
  return 0;
}

int run_query(const QueryOptions& q, const ch03::ProgramOptions& p, Backend backend,
              const BuildOptions& build, TriangleVariant variant, const TracerMaker& make) {
  QueryScene s{ch05::load_obj(q.scene_path), {}, {}, {}};
  s.bvh = build_bvh(s.obj.geometry, build);
  // A ray file needs no camera (and a scene no view can frame may still be traced).
  ProtocolView view;
  if (!q.dump_hits_path.empty()) {
    view = query_view(q, p, s.bvh.bounds);
    const Extent extent = p.size_given() ? p.common.extent() : k_protocol_extent;
    s.camera = make_protocol_camera(view, extent.width, extent.height);
  }
  const TracerScene scene{
      scene_name(q.scene_path), s.obj.geometry, s.bvh, s.camera, backend, variant};
  const std::vector<Tracer> tracers = make(scene);
  if (tracers.empty() || tracers.front().camera_rays_only)
    throw UsageError("this tracer cannot trace rays given to it");
  s.tracer = tracers.front();
  return q.rays_path.empty() ? run_dump_hits(q, backend, s, view)
                             : run_ray_file(q, backend, s.tracer);
}

} // namespace rt::ch07
