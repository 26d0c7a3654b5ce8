// Chapter 07: the chapter's own report. See chapter_report.h.
#include "chapter_report.h"

#include <optional>

#include "bvh_build.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "reference.h"
#include "rt/device_buffer.h"
#include "rt/image.h"
#include "rt/timer.h"
#include "runner.h"
#include "shaded_render.h"

namespace rt::ch07 {
namespace {

// On CPU threads brute force is too slow for a whole frame: it is timed on the reference's
// sampled rays, and the frame time extrapolated from them.
ReportRow cpu_brute_force_row(const ChapterReportOptions& o, const ch04::Mesh& mesh,
                              const ch03::Camera<float>& camera) {
  std::vector<RayF> rays;
  rays.reserve(o.extent.pixel_count());
  for (int j = 0; j < o.extent.height; ++j)
    for (int i = 0; i < o.extent.width; ++i) rays.push_back(camera.ray_through_pixel(i, j));
  const Reference ref = trace_reference(mesh, rays, o.reference_rays);
  std::vector<RayF> sample;
  for (const std::size_t i : ref.index) sample.push_back(rays[i]);
  std::vector<MeshHit> hits;
  const Timing timing =
      time_cpu([&] { hits = ch04::closest_hits_cpu(o.variant, mesh, sample); }, {0, 1});
  const double ms_per_ray = timing.median_ms / double(sample.size());
  std::vector<MeshHit> frame_hits(rays.size());
  for (std::size_t k = 0; k < ref.index.size(); ++k) frame_hits[ref.index[k]] = hits[k];
  ReportRow row{"brute force (chapter 04)", "cpu", ms_per_ray * double(rays.size()),
                1e-3 / ms_per_ray,          "",    {}};
  row.error = error_against(ref, frame_hits, row) + "; timed on the " +
              group_digits(static_cast<long long>(sample.size())) +
              " sampled rays, frame time extrapolated";
  return row;
}

struct ShadedRun {
  Image image;
  Timing timing;
};

// Chapter 06's shading of the frame, through the tree or (GPU only) by brute force with
// chapter 06's own kernel.
ShadedRun shade(const ChapterReportOptions& o, Backend backend, const ch06::ShadedScene& scene,
                const Bvh& bvh, const ch03::Camera<float>& camera, bool tree) {
  const unsigned features = ch06::features_used(scene, o.smooth, o.shadows);
  ShadedRun run{Image(o.extent.width, o.extent.height), {}};
  const TimingPlan plan =
      tree ? timing_plan(backend, o.frames) : TimingPlan{1, o.frames > 0 ? o.frames : 3};
  if (backend == Backend::gpu) {
    const ch06::DeviceShadedScene d_scene(scene, features);
    const DeviceBvh d_bvh(bvh);
    DeviceBuffer<Rgba8> d_pixels(run.image.pixels.size());
    run.timing = time_gpu(
        [&] {
          if (tree)
            render_bvh_shaded(backend, features, with_bvh(d_scene.view(), d_bvh.view()), camera,
                              o.extent, d_pixels.data());
          else
            ch06::render_shaded(backend, ch06::KernelKind::specialised, features,
                                d_scene.view(), camera, o.extent, d_pixels.data());
        },
        plan);
    d_pixels.download(run.image.pixels);
  } else {
    const ch06::SceneView view = ch06::host_view(scene, features);
    run.timing = time_cpu(
        [&] {
          render_bvh_shaded(backend, features, with_bvh(view, bvh.view()), camera, o.extent,
                            run.image.pixels.data());
        },
        plan);
  }
  return run;
}

ReportRow frame_row(std::string variant, Backend backend, const Timing& timing, Extent extent,
                    std::string error) {
  return {std::move(variant),
          to_string(backend),
          timing.median_ms,
          double(extent.pixel_count()) / (timing.median_ms * 1e3),
          format_fixed(1000.0 / timing.median_ms, 1) + " frames/s" + error,
          {{"fps", 1000.0 / timing.median_ms}}};
}

// The shaded frame through the SAH tree on each backend, against brute force on the GPU and,
// on the CPU, against the GPU's frame.
void report_shaded_frames(const ChapterReportOptions& o, const std::vector<Backend>& backends,
                          const ch06::ShadedScene& scene, const Bvh& bvh,
                          const ch03::Camera<float>& camera, Report& report) {
  std::optional<Image> against;
  std::string against_name;
  for (const Backend backend : backends) {
    if (backend == Backend::gpu) {
      ShadedRun brute = shade(o, backend, scene, bvh, camera, false);
      report.add_row(frame_row("shaded frame, brute force (chapter 06)", backend, brute.timing,
                               o.extent, ""));
      against = std::move(brute.image);
      against_name = "brute force";
    }
    ShadedRun run = shade(o, backend, scene, bvh, camera, true);
    long long differing = -1;
    std::string error;
    if (against) {
      differing =
          static_cast<long long>(count_differing_pixels(run.image.pixels, against->pixels));
      error = "; " + group_digits(differing) + " px differ from " + against_name;
    }
    ReportRow row = frame_row("shaded frame, BVH (SAH)", backend, run.timing, o.extent, error);
    row.metrics.emplace_back("pixels_differing", double(differing));
    report.add_row(std::move(row));
    if (backend == Backend::gpu) {
      against = std::move(run.image);
      against_name = "the GPU's frame";
    }
  }
}

} // namespace

void report_chapter(const ChapterReportOptions& o, const std::vector<Backend>& backends,
                    const ch06::ShadedScene& scene, const ch03::Camera<float>& camera,
                    Report& report) {
  BuildOptions median = o.build, sah = o.build;
  median.method = SplitMethod::median;
  sah.method = SplitMethod::sah;
  const Bvh median_tree = build_bvh(scene.mesh, median);
  const Bvh sah_tree = build_bvh(scene.mesh, sah);
  report.add_row(build_row("build, median", median_tree));
  report.add_row(build_row("build, sah", sah_tree));
  // With --split sbvh, the spatial splits' tree too: built, and traced beside the others.
  std::optional<Bvh> sbvh_tree;
  if (o.build.method == SplitMethod::sbvh) {
    sbvh_tree.emplace(build_bvh(scene.mesh, o.build));
    report.add_row(build_row("build, sbvh", *sbvh_tree));
  }

  // Brute force and both trees on the camera's rays, through the runner: each tree's hits
  // against the SAH tree's, every tree's against float64 on sampled rays.
  // The median tree may keep the other of two triangles at exactly the same distance.
  const TracerMaker makers = [&](const TracerScene& s) {
    Tracer median_tracer = bvh_tracer("median", median_tree, s);
    median_tracer.rule = HitRule::ties_allowed;
    std::vector<Tracer> tracers{brute_force_tracer(s), std::move(median_tracer),
                                bvh_tracer("sah", sah_tree, s)};
    if (sbvh_tree) { // its leaves test triangles in another order: ties may go either way
      tracers.push_back(bvh_tracer("sbvh", *sbvh_tree, s));
      tracers.back().rule = HitRule::ties_allowed;
    }
    return tracers;
  };
  for (const Backend backend : backends) {
    RunnerOptions runner;
    runner.extent = o.extent;
    runner.backend = backend;
    runner.variant = o.variant;
    runner.build = sah;
    runner.ray_types = {RayType::primary};
    runner.frames = o.frames;
    runner.reference_rays = o.reference_rays;
    runner.count_work = true;
    run_scene({o.scene_path, &camera}, {makers}, runner, report);
    if (backend == Backend::cpu) report.add_row(cpu_brute_force_row(o, scene.mesh, camera));
  }
  report_shaded_frames(o, backends, scene, sah_tree, camera, report);
}

} // namespace rt::ch07
