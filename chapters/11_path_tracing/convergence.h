// Chapter 11: error against run time for a progressive renderer. A reference of many samples,
// summed in float64, then each variant's image at 1, 2, 4, ... samples per pixel, with the
// time it took to get there and its distance from the reference. An unbiased estimator's mean
// squared error falls as 1 / samples, so as 1 / time: a line of slope -1 on log-log axes,
// shifted down by the variance each sample has and left by what each sample costs.
#pragma once

#include <string>
#include <vector>

#include "path_render.h"
#include "rt/report.h"

namespace rt::ch11 {

// Mean radiance per pixel and channel (r, g, b, r, g, b, ...), in double.
struct Reference {
  std::vector<double> radiance;
  int samples = 0;
  double seconds = 0.0;
};

// `samples` samples per pixel of the megakernel with MIS, numbered from
// k_reference_first_sample (so none is shared with the images measured against it), summed in
// float64 in passes of at most k_reference_pass samples, whose float sums stay accurate.
inline constexpr unsigned k_reference_first_sample = 1u << 30;
inline constexpr int k_reference_pass = 16;
Reference render_reference(ProgressiveRenderer& renderer, const CameraSpec& camera,
                           Extent extent, int samples);

struct ImageError {
  double rmse = 0.0;    // root mean square of (x - ref) over pixels and channels
  double rel_mse = 0.0; // mean of (x - ref)^2 / (ref^2 + 0.01): pbrt's relative MSE
};
ImageError image_error(const std::vector<Vec3f>& image, const std::vector<double>& reference);

// [listing:lowpass_share]
// How much of the error's energy a 3 x 3 box filter keeps: the mean square of the filtered
// error image (luminance, over the pixels whose 3 x 3 neighbourhood is inside the image) over
// that of the error itself. White noise, whose pixels' errors are independent, keeps 1/9 of
// its energy (0.111); error spread as blue noise, where a pixel's error is offset by its
// neighbours', keeps less, and the eye, which averages neighbouring pixels too, sees less.
double lowpass_share(const std::vector<Vec3f>& image, const std::vector<double>& reference,
                     Extent extent);
// [/listing:lowpass_share]

struct ConvergencePoint {
  int samples = 0;
  double wall_ms = 0.0;   // since the first sample, the host waiting for every pass
  double kernel_ms = 0.0; // the kernels alone (CUDA events on the GPU; the wall on the CPU)
  ImageError error;
  unsigned long long non_finite = 0;
  double lowpass = 0.0; // lowpass_share of the error
};

// The variant's image at 1, 2, 4, ... max_samples samples per pixel.
std::vector<ConvergencePoint> measure_convergence(ProgressiveRenderer& renderer,
                                                  const RenderSettings& settings,
                                                  const CameraSpec& camera, Extent extent,
                                                  int max_samples, const Reference& reference);

// The same, but each point a fresh image of that many samples, for which the settings'
// sampler is made (sampler_samples = the point's count: a stratified grid or a zsobol net of
// that size), and timed alone: the samplers that need the count ahead are measured as they
// would be used.
std::vector<ConvergencePoint> measure_sampler_convergence(ProgressiveRenderer& renderer,
                                                          RenderSettings settings,
                                                          const CameraSpec& camera,
                                                          Extent extent, int max_samples,
                                                          const Reference& reference);

// The slope of log MSE against log samples, fitted by least squares over the points with a
// non-zero error: -1 for an unbiased estimator whose samples are independent.
double convergence_slope(const std::vector<ConvergencePoint>& points);

// "megakernel, mis" and the like: a variant's name in the report.
std::string describe(const RenderSettings& settings);

// One report row per point: the variant with its sample count, the time so far, and the
// errors (metrics samples, wall_ms, kernel_ms, rmse, rel_mse, non_finite, error_lowpass).
void add_convergence_rows(Report& report, const std::string& variant, Backend backend,
                          long long pixels, const std::vector<ConvergencePoint>& points);

} // namespace rt::ch11
