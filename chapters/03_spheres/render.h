// Chapter 03: the sphere scene rendered on either backend, its float64 reference, and the
// comparison that fills the report: pixels that differ, primary rays that hit where the
// reference misses (or the other way round), the worst relative error of t, NaN pixels.
#pragma once

#include <vector>

#include "camera_spec.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "scene.h"
#include "spheres.h"
#include "trace.h"

namespace rt::ch03 {

// What the primary ray of a pixel found, kept beside the image for the error metrics.
struct PixelRecord {
  float t;    // hit distance; infinity for none
  int sphere; // -1 for none
  int nan;    // 1 if the pixel's colour came out NaN
  int rays;   // rays the pixel traced: the primary ray and its mirror rays
};

// Fills extent.width * extent.height pixels (device memory for the GPU backend, host memory
// for the CPU one); records, if not null, lives in the same memory space.
void render_spheres(Backend backend, const SphereScene<float>& scene,
                    const Camera<float>& camera, Extent extent, TraceSettings settings,
                    Rgba8* pixels, PixelRecord* records = nullptr);

// The same scene in float64 on the CPU, with the stable intersection, tracing the float
// camera's rays (converted exactly): it measures what happens after the camera.
struct ReferenceFrame {
  Image image;
  std::vector<double> t;   // per pixel, the primary hit distance
  std::vector<int> sphere; // per pixel, the sphere hit, or -1
  long long rays = 0;      // rays traced, primary and mirror
};
ReferenceFrame render_reference(const SphereScene<float>& scene, const CameraSpec& camera,
                                Extent extent, int max_depth);

struct FrameError {
  long long pixels_differing = 0;
  long long false_hits = 0;   // a sphere where the reference sees nothing or another sphere
  long long false_misses = 0; // nothing where the reference sees a sphere
  double max_relative_t_error = 0; // over pixels whose primary ray hit the same sphere
  long long nan_pixels = 0;
};
FrameError compare_with_reference(const Image& image, const std::vector<PixelRecord>& records,
                                  const ReferenceFrame& reference);

} // namespace rt::ch03
