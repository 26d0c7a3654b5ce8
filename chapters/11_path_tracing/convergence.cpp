// Chapter 11: error against run time. See convergence.h.
#include "convergence.h"

#include <chrono>
#include <cmath>

#include "rt/cpu_progress.h"
#include "rt/timer.h"

namespace rt::ch11 {

Reference render_reference(ProgressiveRenderer& renderer, const CameraSpec& camera,
                           Extent extent, int samples) {
  const CpuWorkName name("float64 reference");
  const auto start = std::chrono::steady_clock::now();
  Reference reference;
  reference.radiance.assign(static_cast<std::size_t>(extent.pixel_count()) * 3, 0.0);
  std::vector<double> weight(static_cast<std::size_t>(extent.pixel_count()), 0.0);
  CpuProgress progress(samples, "samples"); // a reference takes minutes on the CPU
  for (int done = 0; done < samples;) {
    const int pass = std::min(k_reference_pass, samples - done);
    renderer.restart(camera, extent, k_reference_first_sample + unsigned(done));
    renderer.add_samples({PathVariant::persistent}, pass); // the megakernel's sums, faster
    const std::vector<float4> sums = renderer.sums();
    for (std::size_t i = 0; i < sums.size(); ++i) {
      reference.radiance[3 * i] += sums[i].x;
      reference.radiance[3 * i + 1] += sums[i].y;
      reference.radiance[3 * i + 2] += sums[i].z;
      weight[i] += sums[i].w;
    }
    done += pass;
    progress.update(done);
  }
  for (std::size_t i = 0; i < weight.size(); ++i)
    for (int c = 0; c < 3; ++c)
      reference.radiance[3 * i + c] /= weight[i] > 0.0 ? weight[i] : 1.0;
  reference.samples = samples;
  reference.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return reference;
}

// [listing:rel_mse]
ImageError image_error(const std::vector<Vec3f>& image, const std::vector<double>& reference) {
  double squared = 0.0, relative = 0.0;
  for (std::size_t i = 0; i < image.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double ref = reference[3 * i + c];
      const double difference = double(image[i][c]) - ref;
      squared += difference * difference;
      relative += difference * difference / (ref * ref + 0.01);
    }
  }
  const double n = 3.0 * static_cast<double>(image.size());
  return {std::sqrt(squared / n), relative / n};
}
// [/listing:rel_mse]

double lowpass_share(const std::vector<Vec3f>& image, const std::vector<double>& reference,
                     Extent extent) {
  const int w = extent.width, h = extent.height;
  if (w < 3 || h < 3) return 0.0;
  std::vector<double> e(image.size());
  for (std::size_t i = 0; i < image.size(); ++i) // luminance, path_sampling.h's weights
    e[i] = 0.2126 * (double(image[i].x) - reference[3 * i]) +
           0.7152 * (double(image[i].y) - reference[3 * i + 1]) +
           0.0722 * (double(image[i].z) - reference[3 * i + 2]);
  double filtered = 0.0, raw = 0.0;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      double box = 0.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) box += e[std::size_t(y + dy) * w + (x + dx)];
      box /= 9.0;
      filtered += box * box;
      const double own = e[std::size_t(y) * w + x];
      raw += own * own;
    }
  return raw > 0.0 ? filtered / raw : 0.0;
}

namespace {

// Adds `samples` samples to the renderer and the time they took to the two clocks.
void add_timed_samples(ProgressiveRenderer& renderer, const RenderSettings& settings,
                       int samples, double& wall_ms, double& kernel_ms) {
  const auto start = std::chrono::steady_clock::now();
  BackendStopwatch kernels(renderer.backend());
  renderer.add_samples(settings, samples);
  kernel_ms += kernels.milliseconds();
  renderer.synchronize();
  wall_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                 .count();
}

ConvergencePoint point_now(const ProgressiveRenderer& renderer, double wall_ms,
                           double kernel_ms, const Reference& reference) {
  const std::vector<Vec3f> image = renderer.mean_radiance();
  return {renderer.samples(),
          wall_ms,
          kernel_ms,
          image_error(image, reference.radiance),
          renderer.non_finite(),
          lowpass_share(image, reference.radiance, renderer.extent())};
}

} // namespace

std::vector<ConvergencePoint> measure_convergence(ProgressiveRenderer& renderer,
                                                  const RenderSettings& settings,
                                                  const CameraSpec& camera, Extent extent,
                                                  int max_samples, const Reference& reference) {
  std::vector<ConvergencePoint> points;
  renderer.restart(camera, extent);
  double wall_ms = 0.0, kernel_ms = 0.0;
  for (int target = 1; target <= max_samples; target *= 2) {
    add_timed_samples(renderer, settings, target - renderer.samples(), wall_ms, kernel_ms);
    points.push_back(point_now(renderer, wall_ms, kernel_ms, reference));
  }
  return points;
}

std::vector<ConvergencePoint> measure_sampler_convergence(ProgressiveRenderer& renderer,
                                                          RenderSettings settings,
                                                          const CameraSpec& camera,
                                                          Extent extent, int max_samples,
                                                          const Reference& reference) {
  std::vector<ConvergencePoint> points;
  for (int target = 1; target <= max_samples; target *= 2) {
    settings.sampler_samples = target;
    renderer.restart(camera, extent);
    double wall_ms = 0.0, kernel_ms = 0.0;
    add_timed_samples(renderer, settings, target, wall_ms, kernel_ms);
    points.push_back(point_now(renderer, wall_ms, kernel_ms, reference));
  }
  return points;
}

double convergence_slope(const std::vector<ConvergencePoint>& points) {
  double n = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (const ConvergencePoint& p : points) {
    if (!(p.error.rmse > 0.0)) continue;
    const double x = std::log(double(p.samples)), y = std::log(p.error.rmse * p.error.rmse);
    n += 1.0;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double d = n * sxx - sx * sx;
  return n >= 2.0 && d > 0.0 ? (n * sxy - sx * sy) / d : 0.0;
}

std::string describe(const RenderSettings& settings) {
  std::string text =
      std::string(to_string(settings.variant)) + ", " + to_string(settings.strategy);
  if (settings.kernel == KernelKind::all_features) text += ", all features";
  if (settings.sampler != SamplerKind::independent)
    text += std::string(", ") + to_string(settings.sampler) + " sampler";
  return text;
}

void add_convergence_rows(Report& report, const std::string& variant, Backend backend,
                          long long pixels, const std::vector<ConvergencePoint>& points) {
  for (const ConvergencePoint& p : points) {
    ReportRow row;
    row.variant = variant + ", " + std::to_string(p.samples) + " spp";
    row.backend = to_string(backend);
    row.ms_per_frame = p.wall_ms;
    row.throughput = p.wall_ms > 0.0 ? double(pixels) * p.samples / (p.wall_ms * 1e3) : 0.0;
    row.error = "relMSE " + format_scientific(p.error.rel_mse, 2) + ", RMSE " +
                format_scientific(p.error.rmse, 2) + ", " + std::to_string(p.non_finite) +
                " NaN/Inf, low-pass share " + format_fixed(p.lowpass, 3);
    row.metrics = {{"samples", p.samples},       {"wall_ms", p.wall_ms},
                   {"kernel_ms", p.kernel_ms},   {"rmse", p.error.rmse},
                   {"rel_mse", p.error.rel_mse}, {"non_finite", double(p.non_finite)},
                   {"error_lowpass", p.lowpass}};
    report.add_row(std::move(row));
  }
}

} // namespace rt::ch11
