// Chapter 07: the benchmark runner. It makes each scene's rays once per ray type (the benchmark
// protocol of book appendix A: primary, ambient occlusion, diffuse), traces chapter 07's tree
// once for the hits every tracer is checked against, then times every registered tracer
// (kernel only on the GPU, as the protocol says), compares its hits with chapter 07's, and
// writes one report row per scene, ray type and tracer, and the summary tables. Later chapters
// add tracers; they never copy this loop.
#pragma once

#include <chrono>
#include <iostream>
#include <string>
#include <vector>

#include "anchors.h"
#include "bvh.h"
#include "camera_spec.h"
#include "rt/backend.h"
#include "rt/launch.h"
#include "rt/report.h"
#include "tracer.h"
#include "triangles.h"

namespace rt::ch07 {

struct RunnerOptions {
  Extent extent = k_protocol_extent;
  Backend backend = Backend::gpu; // resolved
  TriangleVariant variant = TriangleVariant::watertight;
  BuildOptions build; // chapter 07's tree, the one every tracer is checked against
  std::vector<RayType> ray_types{RayType::primary, RayType::ao, RayType::diffuse};
  int frames = 0;               // timed runs; 0: the protocol's (GPU 50 after 5, CPU 5 after 1)
  int check_rays = 0;           // rays per ray type checked against brute force (0: none)
  long long reference_rays = 0; // closest-hit rays per ray type checked against float64
  bool count_work = false;      // nodes and triangles per ray, where a tracer counts them (CPU)
  bool build_rows = false;      // a row for chapter 07's build of each scene
  bool end_to_end = false;      // also time chapter 06's shaded frame through chapter 07's tree
  // Progress lines naming the step (scene, ray type, tracer) whenever this long has passed
  // since the last one; null: none.
  std::ostream* progress = &std::cerr;
  std::chrono::milliseconds progress_period = std::chrono::seconds(5);
};

// The options of a benchmark run by the protocol's rules: every batch checked against brute
// force on k_protocol_check_rays rays.
inline RunnerOptions protocol_runner_options() {
  RunnerOptions o;
  o.check_rays = k_protocol_check_rays;
  return o;
}

// One tracer's figure for one ray type.
struct TracerFigure {
  std::string tracer;
  RayType type = RayType::primary;
  double mrays = 0;
  double bytes_per_triangle = 0;
  long long disagreeing = 0; // rays whose hit breaks the tracer's HitRule against chapter 07
};

// One scene's figures, as the summary tables print them.
struct SceneResult {
  std::string scene;
  long long triangles = 0;
  double build_ms = 0, bytes_per_triangle = 0; // chapter 07's tree
  double frame_ms = 0;                         // end to end, shaded; 0 when not measured
  std::vector<TracerFigure> figures;
  long long problems = 0; // disagreeing rays, and sampled rays that differ from brute force

  const TracerFigure* find(const std::string& tracer, RayType type) const;
};

// The report row of a build: its time, Mtriangles/s, and the tree's statistics.
ReportRow build_row(const std::string& variant, const Bvh& bvh);

// A scene's name in tables: the file name without .obj and .gz ("models/conference.obj.gz"
// is "conference").
std::string scene_name(const std::string& path);

// The benchmark set's scenes, in the order they are measured.
inline constexpr const char* k_benchmark_set[] = {
    "stanford-bunny", "armadillo-100k", "stanford-dragon", "conference", "sponza-dabrovic"};

// The scenes of the benchmark set found in `folder` (k_benchmark_set, as .obj.gz); throws
// InputError, naming the folder and tools/get-models.sh, if none is there.
std::vector<std::string> benchmark_set(const std::string& folder);
// The names of k_benchmark_set that `folder` lacks.
std::vector<std::string> missing_from_benchmark_set(const std::string& folder);

// The protocol on every scene file, with the tracers `makers` make for it: rows go to
// `report`; returns the figures.
std::vector<SceneResult> run_benchmark(const std::vector<std::string>& scenes,
                                       const std::vector<TracerMaker>& makers,
                                       const RunnerOptions& options, Report& report);

// One scene for the runner: an OBJ file, seen through the protocol's view of it
// (protocol_view), or through a chapter's camera (primary rays only; the camera's own extent).
struct SceneInput {
  std::string path;
  const ch03::Camera<float>* camera = nullptr;
};
SceneResult run_scene(const SceneInput& input, const std::vector<TracerMaker>& makers,
                      const RunnerOptions& options, Report& report);

// A chapter's own report: the runner on one scene once per backend of `backends` (the GPU
// first, where there is one), rows into `report`. Work is counted on the CPU only, where asked.
struct BackendRuns {
  std::vector<SceneResult> first; // the first backend's figures: what the tables show
  long long problems = 0;         // every backend's
};
BackendRuns run_scene_on_each(const std::vector<Backend>& backends, const SceneInput& input,
                              const std::vector<TracerMaker>& makers,
                              const RunnerOptions& options, Report& report);

// The summary as a Markdown table for one tracer (what chapter 07's book prints): Mrays/s per
// ray type with the share of the industry's figures for the same GPU where `anchors` has them,
// the build, the memory and the shaded frame.
std::string summary_table(const std::vector<SceneResult>& results, const std::string& tracer,
                          const std::string& device, const Anchors& anchors);

// One Markdown table per ray type: scenes down, tracers across, each against `baseline` (in
// brackets) and, where `anchors` has figures for the device, the industry's figure beside.
std::string tracer_tables(const std::vector<SceneResult>& results, const std::string& baseline,
                          const RunnerOptions& options, const std::string& device,
                          const Anchors& anchors);

// Host rays in, host hits out, through one tracer on the resolved backend (uploads and
// downloads on the GPU): for ray files and tests, not for timing.
std::vector<MeshHit> trace_with(const Tracer& tracer, Backend backend, Query query,
                                std::span<const RayF> rays);

// The runner's context lines for a report: device, image, tree, triangle test, and the timing
// with the runs it really makes (timing_plan of the backend and options.frames).
void add_runner_context(Report& report, const RunnerOptions& options);

} // namespace rt::ch07
