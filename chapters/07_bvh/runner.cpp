// Chapter 07: the benchmark runner. See runner.h.
#include "runner.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>

#include "bvh_build.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "model_render.h"
#include "obj_loader.h"
#include "protocol.h"
#include "reference.h"
#include "rt/cpu_progress.h"
#include "rt/device_buffer.h"
#include "rt/error.h"
#include "rt/timer.h"
#include "shaded_render.h"
#include "shaded_scene.h"

namespace rt::ch07 {
namespace {

Query query_for(RayType type) { return type == RayType::ao ? Query::any : Query::closest; }

// The elements of `all` at `index`.
template <class T>
std::vector<T> pick(std::span<const T> all, const std::vector<std::size_t>& index) {
  std::vector<T> out;
  out.reserve(index.size());
  for (const std::size_t i : index) out.push_back(all[i]);
  return out;
}

// The runner's progress lines. On the CPU one scene takes minutes, in steps of a few seconds
// each (a tracer's timed runs on one batch): too short for the launch helpers' own lines
// (rt/cpu_progress.h), which speak only after five seconds of one call. So the runner says
// what it is doing whenever a period has passed since its last line, "conference, diffuse
// rays, wide8: timed run 3 of 5, 85 s on the scene", and names the step for the launch
// helpers' lines too (CpuWorkName).
class StepProgress {
public:
  explicit StepProgress(const RunnerOptions& o)
      : out_(o.progress), period_(o.progress_period), start_(Clock::now()),
        next_line_(start_ + period_) {}

  // The step now running: "conference, diffuse rays, wide8".
  void begin(std::string step) {
    name_.reset(); // the previous step's name goes before the next one is set
    name_.emplace(step);
    step_ = std::move(step);
    update();
  }
  // A line, if a period has passed since the last one: the step, then `detail` if any.
  void update(const std::string& detail = "") {
    const Clock::time_point now = Clock::now();
    if (out_ == nullptr || now < next_line_) return;
    next_line_ = now + period_;
    const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(now - start_);
    std::cout.flush(); // the report's lines and these stay in order on one terminal
    *out_ << step_ << (detail.empty() ? "" : ": " + detail) << ", " << seconds.count()
          << " s on the scene" << std::endl;
  }
  // Run `done` of `plan`'s runs (warm-ups first) is starting; cheap unless a line is due.
  void update(int done, const TimingPlan& plan) {
    if (out_ == nullptr || Clock::now() < next_line_) return;
    update(done < plan.warmups ? "warm-up"
                               : "timed run " + std::to_string(done - plan.warmups + 1) +
                                     " of " + std::to_string(plan.runs));
  }

private:
  using Clock = std::chrono::steady_clock;
  std::ostream* out_;
  std::chrono::milliseconds period_;
  Clock::time_point start_, next_line_;
  std::string step_;
  std::optional<CpuWorkName> name_;
};

// "conference, diffuse rays": a batch's part of a step's name.
std::string batch_step(const std::string& scene, RayType type) {
  return scene + ", " + to_string(type) + " rays";
}

// An any-hit query answers only "occluded or not": keep just that of each hit.
std::vector<MeshHit> occlusion_only(std::span<const MeshHit> hits) {
  std::vector<MeshHit> out(hits.size());
  for (std::size_t i = 0; i < hits.size(); ++i) out[i] = {0.0f, hits[i].triangle >= 0 ? 0 : -1};
  return out;
}

// The scene as every tracer sees it: the mesh, chapter 07's tree, the camera, and on the GPU
// the same on the device, uploaded once.
struct LoadedScene {
  std::string name;
  ch05::ObjMesh obj;
  Bvh bvh;
  PinholeCamera camera;                      // the protocol's, or the chapter camera's pinhole
  const ch03::Camera<float>* chapter_camera; // null: the protocol's view
  float radius = 0;
  std::optional<DeviceBvh> d_bvh;
  std::optional<DeviceBuffer<Vec3f>> d_vertices;
  std::optional<DeviceBuffer<ch04::IndexedTriangle>> d_triangles;

  const ch04::Mesh& mesh() const { return obj.geometry; }
  ch04::MeshView d_mesh() const {
    return {d_vertices->data(), d_triangles->data(), int(mesh().triangles.size())};
  }
};

// One batch of rays of one type, on the host and (GPU backend) on the device, with chapter
// 07's hits for it: what every tracer is checked against.
struct Batch {
  RayType type = RayType::primary;
  std::vector<RayF> rays;
  std::optional<DeviceBuffer<RayF>> d_rays;
  std::vector<MeshHit> chapter07;
  int count() const { return static_cast<int>(rays.size()); }
  const RayF* device() const { return d_rays ? d_rays->data() : nullptr; }
};

// Chapter 07's hits of a batch, untimed.
std::vector<MeshHit> trace_chapter07(const LoadedScene& s, const RunnerOptions& o,
                                     const Batch& batch) {
  std::vector<MeshHit> hits(batch.rays.size());
  if (o.backend == Backend::gpu) {
    DeviceBuffer<MeshHit> d_hits(batch.rays.size());
    trace_rays_gpu(query_for(batch.type), o.variant, s.d_bvh->view(), batch.device(),
                   batch.count(), d_hits.data());
    d_hits.download(hits);
  } else {
    trace_rays_cpu(query_for(batch.type), o.variant, s.bvh.view(), batch.rays, hits);
  }
  return hits;
}

Batch primary_batch(const LoadedScene& s, const RunnerOptions& o) {
  Batch batch;
  if (s.chapter_camera != nullptr) { // a chapter's camera, pinhole or orthographic
    const ch03::Camera<float>& camera = *s.chapter_camera;
    for (int j = 0; j < o.extent.height; ++j)
      for (int i = 0; i < o.extent.width; ++i)
        batch.rays.push_back(camera.ray_through_pixel(i, j));
    if (o.backend == Backend::gpu) batch.d_rays.emplace(std::span<const RayF>(batch.rays));
  } else if (o.backend == Backend::gpu) {
    batch.d_rays.emplace(o.extent.pixel_count());
    camera_rays_gpu(s.camera, batch.d_rays->data());
    batch.rays = batch.d_rays->to_host();
  } else {
    batch.rays = camera_rays_cpu(s.camera);
  }
  batch.chapter07 = trace_chapter07(s, o, batch);
  return batch;
}

// The ao or diffuse rays from chapter 07's primary hits, made on the backend of the run (the
// GPU's and the CPU's are the same bit for bit).
Batch secondary_batch(const LoadedScene& s, const RunnerOptions& o, RayType type,
                      const Batch& primary) {
  if (s.chapter_camera != nullptr)
    throw Error("the runner's secondary rays need the protocol's camera");
  Batch batch;
  batch.type = type;
  if (o.backend == Backend::gpu) {
    const DeviceBuffer<MeshHit> d_primary{std::span<const MeshHit>(primary.chapter07)};
    DeviceBuffer<RayF> d_rays(primary.rays.size());
    DeviceBuffer<int> d_pixels(primary.rays.size());
    const int count = secondary_rays_gpu(type, s.d_mesh(), d_primary.data(), s.camera, s.radius,
                                         d_rays.data(), d_pixels.data());
    batch.rays.resize(count);
    if (count > 0)
      RT_CUDA_CHECK(cudaMemcpy(batch.rays.data(), d_rays.data(), count * sizeof(RayF),
                               cudaMemcpyDeviceToHost));
    batch.d_rays.emplace(std::span<const RayF>(batch.rays));
  } else {
    batch.rays = secondary_rays_cpu(type, s.mesh(), primary.chapter07, s.camera, s.radius).rays;
  }
  batch.chapter07 = trace_chapter07(s, o, batch);
  return batch;
}

// The checks made once per batch, whatever the tracers: brute force on a sample, and the
// float64 reference on a sample of the closest-hit batches.
struct BatchChecks {
  std::vector<std::size_t> brute_index;
  std::vector<MeshHit> brute;
  std::optional<Reference> reference;
};

BatchChecks batch_checks(const LoadedScene& s, const RunnerOptions& o, const Batch& batch) {
  BatchChecks checks;
  if (o.check_rays > 0) {
    checks.brute_index = every_kth_index(batch.rays.size(), o.check_rays);
    const std::vector<RayF> sample =
        pick(std::span<const RayF>(batch.rays), checks.brute_index);
    if (o.backend == Backend::gpu) {
      const DeviceBuffer<RayF> d_sample{std::span<const RayF>(sample)};
      DeviceBuffer<MeshHit> d_brute(sample.size());
      brute_force_gpu(o.variant, s.d_mesh(), d_sample.data(), int(sample.size()),
                      d_brute.data());
      checks.brute = d_brute.to_host();
    } else {
      // Chapter 07's ray loop rather than chapter 04's rows of 1 024 rays: on a large model
      // a row takes seconds, and this loop's smaller chunks keep the progress lines coming.
      checks.brute.resize(sample.size());
      const ch04::MeshView mesh = ch04::host_view(s.mesh());
      for_each_ray_cpu(sample.size(), [&](std::size_t i) {
        checks.brute[i] = ch04::closest_hit(o.variant, mesh, sample[i]);
      });
    }
  }
  if (o.reference_rays > 0 && batch.type != RayType::ao)
    checks.reference = trace_reference(s.mesh(), batch.rays, o.reference_rays);
  return checks;
}

struct Traced {
  std::vector<MeshHit> hits;
  Timing timing;
};

Traced trace_timed(const Tracer& tracer, const RunnerOptions& o, const Batch& batch,
                   StepProgress& progress) {
  Traced out;
  out.hits.resize(batch.rays.size());
  const Query query = query_for(batch.type);
  const TimingPlan plan = tracer.slow ? TimingPlan{1, o.frames > 0 ? o.frames : 3}
                                      : timing_plan(o.backend, o.frames);
  if (o.backend == Backend::gpu) {
    DeviceBuffer<MeshHit> d_hits(batch.rays.size());
    out.timing = time_gpu(
        [&] { tracer.trace_gpu(query, batch.device(), batch.count(), d_hits.data()); }, plan);
    d_hits.download(out.hits);
  } else {
    // Each run may say where the timing has come: a clock read when no line is due.
    int run = 0;
    out.timing = time_cpu(
        [&] {
          progress.update(run++, plan);
          tracer.trace_cpu(query, batch.rays, out.hits);
        },
        plan);
  }
  return out;
}

// How the hits relate to chapter 07's under the tracer's rule: a sentence and a count.
std::string agreement_text(const Tracer& tracer, const Batch& batch,
                           std::span<const MeshHit> hits, ReportRow& row,
                           long long& disagreeing) {
  const std::string total = group_digits(static_cast<long long>(hits.size()));
  if (tracer.rule == HitRule::identical) {
    disagreeing = 0;
    for (std::size_t i = 0; i < hits.size(); ++i)
      disagreeing += std::memcmp(&hits[i], &batch.chapter07[i], sizeof(MeshHit)) != 0 ? 1 : 0;
    row.metrics.emplace_back("differing_from_ch07", double(disagreeing));
    return disagreeing == 0
               ? "identical to chapter 07's hits"
               : group_digits(disagreeing) + " of " + total + " hits differ from chapter 07's";
  }
  const bool any = batch.type == RayType::ao;
  const HitAgreement a =
      any ? compare_hits(occlusion_only(hits), occlusion_only(batch.chapter07))
          : compare_hits(hits, batch.chapter07);
  disagreeing = a.mismatches;
  row.metrics.emplace_back("differing_from_ch07", double(a.mismatches));
  row.metrics.emplace_back("ties_with_ch07", double(a.ties));
  if (a.mismatches > 0)
    return group_digits(a.mismatches) + " of " + total +
           " rays disagree with chapter 07's hits";
  if (any) return "same occlusion as chapter 07's hits";
  return "chapter 07's hits up to " + group_digits(a.ties) + " exact ties";
}

ReportRow tracer_row(const LoadedScene& s, const RunnerOptions& o, const Tracer& tracer,
                     const Batch& batch, const BatchChecks& checks, StepProgress& progress,
                     TracerFigure& figure) {
  const Traced traced = trace_timed(tracer, o, batch, progress);
  const double mrays =
      batch.rays.empty() ? 0.0 : double(batch.rays.size()) / (traced.timing.median_ms * 1e3);
  ReportRow row{s.name + ", " + to_string(batch.type) + ", " + tracer.name,
                to_string(o.backend),
                traced.timing.median_ms,
                mrays,
                "",
                {{"rays", double(batch.rays.size())}, {"mrays_per_s", mrays}}};
  row.error = agreement_text(tracer, batch, traced.hits, row, figure.disagreeing);
  if (!checks.brute_index.empty()) {
    std::vector<MeshHit> sample =
        pick(std::span<const MeshHit>(traced.hits), checks.brute_index);
    const HitAgreement a =
        batch.type == RayType::ao
            ? compare_hits(occlusion_only(sample), occlusion_only(checks.brute))
            : compare_hits(sample, checks.brute);
    row.error += "; " + group_digits(a.mismatches) + " of " +
                 group_digits(static_cast<long long>(sample.size())) +
                 " sampled rays differ from brute force";
    if (a.ties > 0) row.error += " (" + group_digits(a.ties) + " exact ties)";
    row.metrics.emplace_back("mismatches", double(a.mismatches));
    row.metrics.emplace_back("ties", double(a.ties));
    figure.disagreeing += a.mismatches;
  }
  if (batch.type == RayType::primary) {
    const auto hit = std::count_if(traced.hits.begin(), traced.hits.end(),
                                   [](const MeshHit& h) { return h.triangle >= 0; });
    row.error += "; " + format_fixed(100.0 * double(hit) / double(traced.hits.size()), 1) +
                 "% of pixels hit";
  }
  if (checks.reference) row.error += "; " + error_against(*checks.reference, traced.hits, row);
  if (o.count_work && tracer.work) {
    progress.update("counting the work per ray");
    const TraversalWork work = tracer.work(query_for(batch.type), batch.rays);
    row.error += "; " + format_fixed(work.nodes_per_ray, 1) + " nodes, " +
                 format_fixed(work.triangles_per_ray, 1) + " triangles per ray";
    row.metrics.emplace_back("nodes_per_ray", work.nodes_per_ray);
    row.metrics.emplace_back("triangles_per_ray", work.triangles_per_ray);
  }
  if (o.backend == Backend::gpu && tracer.registers) {
    const int registers = tracer.registers(query_for(batch.type));
    row.error += "; " + std::to_string(registers) + " regs";
    row.metrics.emplace_back("registers", registers);
  }
  figure.tracer = tracer.name;
  figure.type = batch.type;
  figure.mrays = mrays;
  figure.bytes_per_triangle = tracer.bytes_per_triangle;
  return row;
}

// The end-to-end frame: camera rays, the tree, chapter 06's Lambertian shading with smooth
// normals and a shadow ray per light, and 8-bit pixels written, at the benchmark's size.
ReportRow shaded_frame_row(const LoadedScene& s, const RunnerOptions& o, StepProgress& progress,
                           double& frame_ms) {
  const ch06::ShadedScene scene = ch06::scene_from_obj(s.obj, ch06::LightSettings{});
  const unsigned features = ch06::features_used(scene, true, true);
  ch03::Camera<float> camera;
  camera.pinhole = s.camera;
  const Extent extent = o.extent;
  std::vector<ch06::ShadedPixelRecord> records(extent.pixel_count());
  Timing timing;
  if (o.backend == Backend::gpu) {
    const ch06::DeviceShadedScene d_scene(scene, features);
    const BvhSceneView view = with_bvh(d_scene.view(), s.d_bvh->view());
    DeviceBuffer<Rgba8> d_pixels(extent.pixel_count());
    DeviceBuffer<ch06::ShadedPixelRecord> d_records(extent.pixel_count());
    const auto render = [&](ch06::ShadedPixelRecord* d_out) {
      render_bvh_shaded(Backend::gpu, features, view, camera, extent, d_pixels.data(), d_out);
    };
    timing = time_on(
        Backend::gpu, [&] { render(nullptr); }, o.frames);
    render(d_records.data());
    d_records.download(records);
  } else {
    const BvhSceneView view = with_bvh(ch06::host_view(scene, features), s.bvh.view());
    std::vector<Rgba8> pixels(extent.pixel_count());
    const auto render = [&](ch06::ShadedPixelRecord* out) {
      render_bvh_shaded(Backend::cpu, features, view, camera, extent, pixels.data(), out);
    };
    const TimingPlan plan = timing_plan(Backend::cpu, o.frames);
    int run = 0;
    timing = time_cpu(
        [&] {
          progress.update(run++, plan);
          render(nullptr);
        },
        plan);
    render(records.data());
  }
  long long shadow_rays = 0;
  for (const auto& r : records) shadow_rays += r.shadow_rays;
  frame_ms = timing.median_ms;
  return {s.name + ", shaded frame (end to end)",
          to_string(o.backend),
          timing.median_ms,
          double(extent.pixel_count() + shadow_rays) / (timing.median_ms * 1e3),
          format_fixed(1000.0 / timing.median_ms, 1) +
              " frames/s: camera rays, tree, smooth Lambert, " + group_digits(shadow_rays) +
              " shadow rays, 8-bit pixels",
          {{"fps", 1000.0 / timing.median_ms}, {"shadow_rays", double(shadow_rays)}}};
}

LoadedScene load_scene(const SceneInput& input, const RunnerOptions& o) {
  LoadedScene s;
  s.name = scene_name(input.path);
  s.obj = ch05::load_obj(input.path);
  s.chapter_camera = input.camera;
  s.bvh = build_bvh(s.mesh(), o.build);
  s.camera = input.camera != nullptr
                 ? input.camera->pinhole
                 : make_protocol_camera(protocol_view(input.path, s.bvh.bounds), o.extent.width,
                                        o.extent.height);
  s.radius = scene_radius(s.bvh.bounds);
  if (o.backend == Backend::gpu) {
    const ch04::Mesh& mesh = s.mesh();
    ch05::check_device_memory(s.bvh.nodes.size() * sizeof(BvhNode) +
                                  s.bvh.triangles.size() * (sizeof(TriangleF) + sizeof(int)) +
                                  mesh.vertices.size() * sizeof(Vec3f) +
                                  mesh.triangles.size() * sizeof(ch04::IndexedTriangle) +
                                  std::size_t(o.extent.pixel_count()) *
                                      (3 * sizeof(RayF) + 3 * sizeof(MeshHit)),
                              s.name);
    s.d_bvh.emplace(s.bvh);
    s.d_vertices.emplace(std::span<const Vec3f>(mesh.vertices));
    s.d_triangles.emplace(std::span<const ch04::IndexedTriangle>(mesh.triangles));
  }
  return s;
}

} // namespace

const TracerFigure* SceneResult::find(const std::string& tracer, RayType type) const {
  for (const TracerFigure& f : figures)
    if (f.tracer == tracer && f.type == type) return &f;
  return nullptr;
}

ReportRow build_row(const std::string& variant, const Bvh& bvh) {
  const BuildStats& s = bvh.stats;
  // The mesh's triangles: spatial splits copy some into several leaves, so the copies can be
  // more (a tree not from build_bvh has no count, and holds each triangle once).
  const double references = double(bvh.triangles.size());
  const double triangles = s.triangles > 0 ? double(s.triangles) : references;
  const double per_triangle = triangles > 0.0 ? references / triangles : 1.0;
  ReportRow row{variant,
                "cpu",
                s.build_ms,
                triangles / (s.build_ms * 1e3),
                group_digits(s.nodes) + " nodes, depth " + std::to_string(s.depth) +
                    ", SAH cost " + format_fixed(s.sah_cost, 1) + ", " +
                    format_fixed(s.bytes_per_triangle, 1) + " B/triangle" +
                    (references != triangles
                         ? ", " + format_fixed(per_triangle, 3) + " references/triangle"
                         : std::string()) +
                    " (Mtriangles/s)",
                {{"triangles", triangles},
                 {"nodes", double(s.nodes)},
                 {"depth", double(s.depth)},
                 {"sah_cost", s.sah_cost},
                 {"bytes_per_triangle", s.bytes_per_triangle}}};
  if (bvh.options.method == SplitMethod::sbvh)
    row.metrics.push_back({"references_per_triangle", per_triangle});
  return row;
}

std::string scene_name(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  for (const std::string suffix : {".gz", ".obj"})
    if (name.size() > suffix.size() && name.ends_with(suffix))
      name.resize(name.size() - suffix.size());
  return name;
}

namespace {

// The file of a benchmark scene in `folder`, if it is there.
std::optional<std::string> benchmark_file(const std::string& folder, const std::string& name) {
  const std::filesystem::path path = std::filesystem::path(folder) / (name + ".obj.gz");
  std::error_code ignored;
  if (!std::filesystem::is_regular_file(path, ignored)) return std::nullopt;
  return path.string();
}

} // namespace

std::vector<std::string> benchmark_set(const std::string& folder) {
  std::vector<std::string> found;
  for (const char* name : k_benchmark_set)
    if (const std::optional<std::string> path = benchmark_file(folder, name))
      found.push_back(*path);
  if (found.empty())
    throw InputError("--benchmark: no scenes given and none of the benchmark set in " + folder +
                     " (tools/get-models.sh fetches it, or name OBJ files)");
  return found;
}

std::vector<std::string> missing_from_benchmark_set(const std::string& folder) {
  std::vector<std::string> missing;
  for (const char* name : k_benchmark_set)
    if (!benchmark_file(folder, name)) missing.push_back(name);
  return missing;
}

// [listing:run_scene]
SceneResult run_scene(const SceneInput& input, const std::vector<TracerMaker>& makers,
                      const RunnerOptions& o, Report& report) {
  StepProgress progress(o); // every step named, a line every few seconds
  progress.begin(scene_name(input.path) + ": loading, chapter 07's tree");
  const LoadedScene s = load_scene(input, o);
  const TracerScene scene{s.name, s.mesh(), s.bvh, s.camera, o.backend, o.variant};
  progress.begin(s.name + ": the tracers' trees");
  std::vector<Tracer> tracers;
  for (const TracerMaker& make : makers)
    for (Tracer& t : make(scene))
      if (t.runs_on(o.backend)) tracers.push_back(std::move(t));

  SceneResult result;
  result.scene = s.name;
  result.triangles = static_cast<long long>(s.mesh().triangles.size());
  result.build_ms = s.bvh.stats.build_ms;
  result.bytes_per_triangle = s.bvh.stats.bytes_per_triangle;
  // The primary batch always: the secondary rays start from chapter 07's primary hits.
  progress.begin(batch_step(s.name, RayType::primary) + ": the rays, chapter 07's hits");
  const Batch primary = primary_batch(s, o);
  for (const RayType type : o.ray_types) {
    progress.begin(batch_step(s.name, type) + ": the rays, chapter 07's hits, the checks");
    std::optional<Batch> secondary;
    if (type != RayType::primary) secondary = secondary_batch(s, o, type, primary);
    const Batch& batch = secondary ? *secondary : primary;
    const BatchChecks checks = batch_checks(s, o, batch);
    for (const Tracer& tracer : tracers) {
      if (tracer.camera_rays_only && type != RayType::primary) continue;
      progress.begin(batch_step(s.name, type) + ", " + tracer.name);
      TracerFigure figure;
      report.add_row(tracer_row(s, o, tracer, batch, checks, progress, figure));
      result.problems += figure.disagreeing;
      result.figures.push_back(figure);
    }
  }
  if (o.build_rows)
    report.add_row(build_row(
        s.name + ", build (" + std::string(to_string(o.build.method)) + ", CPU)", s.bvh));
  if (o.end_to_end) {
    progress.begin(s.name + ": the shaded frame");
    report.add_row(shaded_frame_row(s, o, progress, result.frame_ms));
  }
  return result;
}
// [/listing:run_scene]

std::vector<SceneResult> run_benchmark(const std::vector<std::string>& scenes,
                                       const std::vector<TracerMaker>& makers,
                                       const RunnerOptions& o, Report& report) {
  std::vector<SceneResult> results;
  for (const std::string& path : scenes)
    results.push_back(run_scene({path}, makers, o, report));
  return results;
}

BackendRuns run_scene_on_each(const std::vector<Backend>& backends, const SceneInput& input,
                              const std::vector<TracerMaker>& makers,
                              const RunnerOptions& options, Report& report) {
  BackendRuns runs;
  for (const Backend backend : backends) {
    RunnerOptions o = options;
    o.backend = backend;
    o.count_work = options.count_work && backend == Backend::cpu;
    const SceneResult result = run_scene(input, makers, o, report);
    if (runs.first.empty()) runs.first.push_back(result);
    runs.problems += result.problems;
  }
  return runs;
}

std::vector<MeshHit> trace_with(const Tracer& tracer, Backend backend, Query query,
                                std::span<const RayF> rays) {
  if (!tracer.runs_on(backend))
    throw UsageError("the tracer '" + tracer.name + "' does not run on the " +
                     to_string(backend));
  std::vector<MeshHit> hits(rays.size());
  if (rays.empty()) return hits;
  if (backend == Backend::gpu) {
    const DeviceBuffer<RayF> d_rays{rays};
    DeviceBuffer<MeshHit> d_hits(rays.size());
    tracer.trace_gpu(query, d_rays.data(), int(rays.size()), d_hits.data());
    d_hits.download(hits);
  } else {
    tracer.trace_cpu(query, rays, hits);
  }
  return hits;
}

void add_runner_context(Report& report, const RunnerOptions& o) {
  report.add_context("device", describe_backend(o.backend));
  report.add_context("image",
                     std::to_string(o.extent.width) + "x" + std::to_string(o.extent.height));
  report.add_context("tree", std::string(to_string(o.build.method)) + ", leaves of up to " +
                                 std::to_string(o.build.max_leaf_size) + " triangles, " +
                                 std::to_string(o.build.bins) + " bins");
  report.add_context("triangle test", ch04::to_string(o.variant));
  const TimingPlan plan = timing_plan(o.backend, o.frames);
  const std::string runs = "median of " + std::to_string(plan.runs) + " after " +
                           std::to_string(plan.warmups) +
                           (plan.warmups == 1 ? " warm-up" : " warm-ups");
  report.add_context("timing",
                     o.backend == Backend::gpu
                         ? "kernel only: CUDA events, " + runs
                         : runs + ", " + std::to_string(cpu_thread_count()) + " CPU threads");
}

namespace {

std::string mrays_text(double mrays) { return format_fixed(mrays, mrays < 100 ? 1 : 0); }

// The tracers of `results` that have a figure for `type`, in the order they first appear.
std::vector<std::string> tracer_names(const std::vector<SceneResult>& results, RayType type) {
  std::vector<std::string> names;
  for (const SceneResult& r : results)
    for (const TracerFigure& f : r.figures)
      if (f.type == type && std::find(names.begin(), names.end(), f.tracer) == names.end())
        names.push_back(f.tracer);
  return names;
}

} // namespace

std::string summary_table(const std::vector<SceneResult>& results, const std::string& tracer,
                          const std::string& device, const Anchors& anchors) {
  const AnchorSet* set = anchors.for_device(device);
  std::ostringstream out;
  out << "| scene | triangles | primary | ao | diffuse | build ms | bytes/triangle | frame ms "
         "(fps) |\n|---|---|---|---|---|---|---|---|\n";
  bool any_anchor = false;
  for (const SceneResult& r : results) {
    const AnchorFigures* a = find_scene(set, r.scene);
    any_anchor = any_anchor || a != nullptr;
    out << "| " << r.scene << " | " << group_digits(r.triangles) << " |";
    double bytes = r.bytes_per_triangle;
    for (const RayType type : {RayType::primary, RayType::ao, RayType::diffuse}) {
      const TracerFigure* f = r.find(tracer, type);
      if (f == nullptr) {
        out << " - |";
        continue;
      }
      bytes = f->bytes_per_triangle;
      out << " " << mrays_text(f->mrays);
      if (a != nullptr && a->for_type(type) > 0)
        out << " (" << format_fixed(100.0 * f->mrays / a->for_type(type), 0) << "%)";
      out << " |";
    }
    out << " " << format_fixed(r.build_ms, 0) << " | " << format_fixed(bytes, 0) << " | "
        << (r.frame_ms > 0 ? format_fixed(r.frame_ms, 2) + " (" +
                                 format_fixed(1000.0 / r.frame_ms, 0) + ")"
                           : std::string("-"))
        << " |\n";
  }
  out << "Mrays/s of " << tracer << " on " << device << ", kernel only, median.";
  if (any_anchor)
    out << " In brackets: share of " << set->system << "'s figure on the same GPU.";
  out << "\n";
  return out.str();
}

std::string tracer_tables(const std::vector<SceneResult>& results, const std::string& baseline,
                          const RunnerOptions& o, const std::string& device,
                          const Anchors& anchors) {
  const AnchorSet* set = anchors.for_device(device);
  std::ostringstream out;
  for (const RayType type : o.ray_types) {
    const std::vector<std::string> names = tracer_names(results, type);
    out << "\n"
        << to_string(type) << " rays, Mrays/s on " << device << " (in brackets: against "
        << baseline << ")\n\n| scene |";
    if (set != nullptr) out << " " << set->system << " |";
    for (const std::string& name : names) out << " " << name << " |";
    out << "\n|---|";
    for (std::size_t k = 0; k < names.size() + (set != nullptr ? 1 : 0); ++k) out << "---|";
    out << "\n";
    for (const SceneResult& r : results) {
      const TracerFigure* base = r.find(baseline, type);
      out << "| " << r.scene << " |";
      if (set != nullptr) {
        const AnchorFigures* a = find_scene(set, r.scene);
        out << " "
            << (a != nullptr && a->for_type(type) > 0 ? mrays_text(a->for_type(type))
                                                      : std::string("-"))
            << " |";
      }
      for (const std::string& name : names) {
        const TracerFigure* f = r.find(name, type);
        if (f == nullptr) {
          out << " - |";
          continue;
        }
        out << " " << mrays_text(f->mrays);
        if (base != nullptr && base->mrays > 0)
          out << " (" << format_fixed(f->mrays / base->mrays, 2) << "x)";
        if (f->disagreeing > 0) out << " DIFFERS";
        out << " |";
      }
      out << "\n";
    }
  }
  return out.str();
}

} // namespace rt::ch07
