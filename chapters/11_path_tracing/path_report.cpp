// Chapter 11: the program's reports. See path_report.h.
#include "path_report.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "animation.h"
#include "rt/cpu_progress.h"
#include "rt/program_output.h"
#include "rt/timer.h"
#include "wavefront.h"

namespace rt::ch11 {
namespace {

// Pixels whose radiance sums differ at all between two images of the same size.
long long pixels_differing(const std::vector<float4>& a, const std::vector<float4>& b) {
  long long differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    differ += (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z);
  return differ;
}

} // namespace

void add_kernel_rows(ProgressiveRenderer& renderer, const RenderSettings& settings,
                     const CameraSpec& camera, Extent extent, int frames, Report& report) {
  const Strategy strategy = settings.strategy;
  RenderSettings variants[] = {{PathVariant::megakernel, KernelKind::specialised, strategy},
                               {PathVariant::megakernel, KernelKind::all_features, strategy},
                               {PathVariant::persistent, KernelKind::specialised, strategy},
                               {PathVariant::wavefront, KernelKind::specialised, strategy}};
  for (RenderSettings& v : variants) {
    v.sampler = settings.sampler;
    v.sampler_samples = settings.sampler_samples;
  }
  report.add_context("kernels", "specialised on " + renderer.describe_features() +
                                    "; all features: every feature compiled in, switched by "
                                    "the scene's flags");
  renderer.restart(camera, extent);
  const RayCounts rays = renderer.add_counted_sample(strategy);
  const double rays_per_path = double(rays.total()) / double(extent.pixel_count());
  report.add_context(
      "rays per path",
      format_fixed(rays_per_path, 2) + " (" +
          format_fixed(double(rays.extension) / double(extent.pixel_count()), 2) +
          " camera and bounce, " +
          format_fixed(double(rays.shadow) / double(extent.pixel_count()), 2) +
          " shadow; sample 0, counted by the wavefront)");
  std::vector<float4> first;
  double first_ms = 0.0;
  for (const RenderSettings& v : variants) {
    renderer.restart(camera, extent);
    const Timing t = time_on(
        renderer.backend(), [&] { renderer.add_samples(v, 1); }, frames);
    const std::vector<float4> sums = renderer.sums();
    if (first.empty()) {
      first = sums;
      first_ms = t.median_ms;
    }
    const long long differ = pixels_differing(sums, first);
    const double non_finite = double(renderer.non_finite());
    const double mpaths = double(extent.pixel_count()) / (t.median_ms * 1e3);
    const double mrays = mpaths * rays_per_path; // every camera, bounce and shadow ray
    ReportRow row{describe(v) + (v.kernel == KernelKind::specialised ? " (specialised)" : ""),
                  to_string(renderer.backend()),
                  t.median_ms,
                  mpaths,
                  format_fixed(t.median_ms / first_ms, 2) + "x the first row's time, " +
                      group_digits(differ) + " px differ from it, " +
                      group_digits(static_cast<long long>(non_finite)) + " NaN/Inf samples, " +
                      format_fixed(mrays, 1) + " Mrays/s",
                  {{"time_vs_first", t.median_ms / first_ms},
                   {"pixels_differing", double(differ)},
                   {"non_finite", non_finite},
                   {"rays_per_path", rays_per_path},
                   {"mrays_per_s", mrays}}};
    if (renderer.backend() == Backend::gpu) { // what the features cost the GPU: registers
      const int registers = renderer.registers(v);
      row.error += ", " + std::to_string(registers) + " registers";
      row.metrics.push_back({"registers", registers});
    }
    report.add_row(std::move(row));
  }
  if (renderer.backend() == Backend::gpu)
    add_tail_row(renderer, variants[3], camera, extent, frames, rays_per_path, first_ms,
                 report);
}

void add_tail_row(ProgressiveRenderer& renderer, const RenderSettings& wavefront,
                  const CameraSpec& camera, Extent extent, int frames, double rays_per_path,
                  double first_ms, Report& report) {
  constexpr int k = k_samples_a_call;
  const auto sums_after = [&](const RenderSettings& settings) {
    renderer.restart(camera, extent);
    renderer.add_samples(settings, k);
    return renderer.sums();
  };
  const std::vector<float4> mega =
      sums_after({PathVariant::megakernel, KernelKind::specialised, wavefront.strategy,
                  wavefront.sampler, wavefront.sampler_samples});
  const long long differ = pixels_differing(sums_after(wavefront), mega);
  renderer.restart(camera, extent);
  const Timing t = time_on(
      renderer.backend(), [&] { renderer.add_samples(wavefront, k); }, frames);
  const double ms = t.median_ms / k;
  const double mpaths = double(extent.pixel_count()) / (ms * 1e3);
  report.add_row({describe(wavefront) + " (specialised), " + std::to_string(k) +
                      " samples a call: stragglers beside the next sample",
                  to_string(renderer.backend()),
                  ms,
                  mpaths,
                  format_fixed(ms / first_ms, 2) + "x the first row's time, " +
                      group_digits(differ) + " px differ from the megakernel's " +
                      std::to_string(k) + " samples, " +
                      format_fixed(mpaths * rays_per_path, 1) + " Mrays/s",
                  {{"time_vs_first", ms / first_ms},
                   {"pixels_differing", double(differ)},
                   {"samples_per_call", double(k)},
                   {"mrays_per_s", mpaths * rays_per_path}}});
}

void add_moving_rows(MovingPathRenderer& renderer, const RenderSettings& settings,
                     const CameraSpec& camera, Extent extent, int frames, Report& report,
                     std::ostream& progress, std::chrono::milliseconds period) {
  frames = moving_frame_count(frames);
  double animate = 0, tree = 0, collapse = 0, render = 0, wall = 0;
  renderer.restart(camera, extent);
  BackendClock clock(renderer.backend(), 2); // around the sample
  const CpuWorkName name("moving scene");
  CpuProgress line(frames, "frames", progress, period);
  for (int f = 0; f < frames; ++f) {
    const auto start = std::chrono::steady_clock::now();
    const ch10::FrameParts parts = renderer.move_to(f * ch10::k_seconds_per_frame);
    clock.mark(0);
    renderer.add_samples(settings, 1);
    clock.mark(1);
    render += clock.milliseconds_between(0, 1); // waits for the sample
    wall += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
    animate += parts.animate_ms, tree += parts.tree_ms, collapse += parts.collapse_ms;
    line.update(f + 1);
  }
  const double n = frames, ms = (animate + tree + collapse + render) / n;
  const double non_finite = double(renderer.non_finite());
  report.add_row(
      {describe(settings) + ", moving: tree every frame, on the backend",
       to_string(renderer.backend()),
       ms,
       double(extent.pixel_count()) / (ms * 1e3),
       format_fixed(animate / n, 2) + " ms animate + " + format_fixed(tree / n, 2) +
           " ms tree + " + format_fixed(collapse / n, 2) + " ms collapse + " +
           format_fixed(render / n, 2) + " ms render; " + format_fixed(1e3 * n / wall, 1) +
           " frames/s wall clock over " + std::to_string(frames) + " frames; " +
           group_digits(static_cast<long long>(non_finite)) + " NaN/Inf samples in the last",
       {{"animate_ms", animate / n},
        {"tree_ms", tree / n},
        {"collapse_ms", collapse / n},
        {"render_ms", render / n},
        {"wall_fps", 1e3 * n / wall},
        {"non_finite", non_finite}}});
}

SamplesTaken add_image_samples(ProgressiveRenderer& renderer, const RenderSettings& settings,
                               int spp, double seconds, std::ostream& progress,
                               std::chrono::milliseconds period) {
  const CpuWorkName name("rendering the image");
  const long long paths =
      renderer.backend() == Backend::gpu ? k_gpu_paths_per_pass : k_paths_per_pass;
  const int per_pass = static_cast<int>(
      std::clamp<long long>(paths / std::max<long long>(renderer.extent().pixel_count(), 1), 1,
                            k_max_samples_per_pixel));
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const int most = seconds > 0.0 ? k_max_samples_per_pixel : spp;
  CpuProgress line(seconds > 0.0 ? static_cast<long long>(std::ceil(seconds)) : spp,
                   seconds > 0.0 ? "s" : "samples", progress, period);
  int done = 0;
  while (done < most) {
    const int pass = std::min(per_pass, most - done);
    renderer.add_samples(settings, pass);
    renderer.synchronize(); // the pass is done when the line says so
    done += pass;
    if (seconds > 0.0) {
      const double so_far = elapsed();
      line.update(static_cast<long long>(so_far));
      if (so_far >= seconds) break;
    } else {
      line.update(done);
    }
  }
  return {done, elapsed()};
}

namespace {

// A report of error against run time with its context, and the float64 reference it measures
// against.
Report start_error_report(const std::string& title, Backend backend, int reference_samples) {
  return start_report(title, "Mpaths/s",
                      "float64 mean of " + std::to_string(reference_samples) + " spp (mis)",
                      backend);
}
Reference add_reference(Report& report, ProgressiveRenderer& renderer, const std::string& scene,
                        const CameraSpec& camera, Extent extent, int reference_samples) {
  report.add_context("scene", scene);
  report.add_context("resolution", to_string(extent));
  Reference reference = render_reference(renderer, camera, extent, reference_samples);
  report.add_context("reference seconds", format_fixed(reference.seconds, 1));
  return reference;
}

} // namespace

Report convergence_report(ProgressiveRenderer& renderer, const std::string& title,
                          const std::string& scene, const CameraSpec& camera, Extent extent,
                          int max_samples, int reference_samples) {
  const Backend backend = renderer.backend();
  Report report = start_error_report(title, backend, reference_samples);
  const Reference reference =
      add_reference(report, renderer, scene, camera, extent, reference_samples);
  const RenderSettings variants[] = {
      {PathVariant::persistent, KernelKind::specialised, Strategy::bsdf},
      {PathVariant::persistent, KernelKind::specialised, Strategy::light},
      {PathVariant::persistent, KernelKind::specialised, Strategy::mis},
      {PathVariant::megakernel, KernelKind::specialised, Strategy::mis},
      {PathVariant::wavefront, KernelKind::specialised, Strategy::mis}};
  for (const RenderSettings& v : variants)
    add_convergence_rows(
        report, describe(v), backend, extent.pixel_count(),
        measure_convergence(renderer, v, camera, extent, max_samples, reference));
  return report;
}

Report sampler_convergence_report(ProgressiveRenderer& renderer, const std::string& title,
                                  const std::string& scene, const CameraSpec& camera,
                                  Extent extent, int max_samples, int reference_samples) {
  const Backend backend = renderer.backend();
  Report report = start_error_report(title, backend, reference_samples);
  const Reference reference =
      add_reference(report, renderer, scene, camera, extent, reference_samples);
  double independent_mse = 0.0;
  for (const SamplerKind kind : k_samplers) {
    RenderSettings settings{PathVariant::persistent, KernelKind::specialised, Strategy::mis};
    settings.sampler = kind;
    const std::vector<ConvergencePoint> points =
        measure_sampler_convergence(renderer, settings, camera, extent, max_samples, reference);
    add_convergence_rows(report, describe(settings), backend, extent.pixel_count(), points);
    const double mse = points.back().error.rmse * points.back().error.rmse;
    if (kind == SamplerKind::independent) independent_mse = mse;
    report.add_context(
        std::string("sampler ") + to_string(kind),
        "MSE slope " + format_fixed(convergence_slope(points), 2) + "; at " +
            std::to_string(points.back().samples) + " spp, MSE " +
            format_fixed(independent_mse > 0.0 ? mse / independent_mse : 0.0, 3) +
            "x the independent sampler's, " + format_fixed(points.back().wall_ms, 1) + " ms");
  }
  return report;
}

} // namespace rt::ch11
