// Chapter 11 test cases: small renders on either backend and the statistics the analytic tests
// compare them with, shared by the test files.
#pragma once

#include <cmath>
#include <vector>

#include "path_render.h"

namespace rt::ch11::testing {

inline const char* k_room = RT_ASSETS_DIR "/cornell_room.obj.gz";

// The mean over pixels and channels of the per-pixel means, and its standard error, taking
// each pixel's mean (of the same number of independent samples) as one draw.
struct MeanAndError {
  double mean = 0.0;
  double standard_error = 0.0;
};

inline MeanAndError pixel_statistics(const std::vector<Vec3f>& image) {
  double sum = 0.0, squares = 0.0;
  for (const Vec3f& p : image) {
    const double v = (double(p.x) + p.y + p.z) / 3.0;
    sum += v;
    squares += v * v;
  }
  const double n = static_cast<double>(image.size());
  const double mean = sum / n;
  const double variance = (squares - n * mean * mean) / (n - 1.0);
  return {mean, std::sqrt(std::max(variance, 0.0) / n)};
}

// `samples` samples per pixel of `scene` seen by `camera`.
inline std::vector<float4> render_sums(const PathScene& scene, Backend backend,
                                       const CameraSpec& camera, Extent extent, int samples,
                                       const RenderSettings& settings = {}) {
  PathRenderer renderer(scene, backend);
  renderer.restart(camera, extent);
  renderer.add_samples(settings, samples);
  return renderer.sums();
}

inline std::vector<Vec3f> render_mean(const PathScene& scene, Backend backend,
                                      const CameraSpec& camera, Extent extent, int samples,
                                      const RenderSettings& settings = {},
                                      unsigned long long* non_finite = nullptr) {
  PathRenderer renderer(scene, backend);
  renderer.restart(camera, extent);
  renderer.add_samples(settings, samples);
  if (non_finite != nullptr) *non_finite = renderer.non_finite();
  return renderer.mean_radiance();
}

// Chapter 10's moving scene at `time`, under the sky and sun the program gives it: it has no
// emitters, so without them every image of it would be black and any two would agree.
inline PathScene lit_moving_scene(double time, int detail) {
  PathScene scene = moving_path_scene(time, detail);
  scene.environment.sky = {0.6f, 0.6f, 0.6f};
  scene.environment.sun_direction = normalize(Vec3f{0.4f, 1.0f, 0.3f});
  scene.environment.sun_irradiance = {3.0f, 2.85f, 2.55f};
  return scene;
}

inline bool same_sums(const std::vector<float4>& a, const std::vector<float4>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z || a[i].w != b[i].w)
      return false;
  return true;
}

} // namespace rt::ch11::testing
