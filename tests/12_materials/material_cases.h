// Chapter 12 test cases: small renders of scenes with materials on either backend, shared by
// the test files. The statistics are chapter 11's (path_cases.h).
#pragma once

#include <vector>

#include "11_path_tracing/path_cases.h"
#include "material_render.h"
#include "material_report.h"
#include "material_scenes.h"
#include "scene_loaders.h"

namespace rt::ch12::testing {

using ch11::testing::MeanAndError;
using ch11::testing::pixel_statistics;

inline const char* k_room_gltf = RT_ASSETS_DIR "/material_room.gltf";
inline const char* k_room_obj = RT_ASSETS_DIR "/material_room.obj.gz";

struct Render {
  std::vector<float4> sums;
  std::vector<Vec3f> mean;
  unsigned long long non_finite = 0;
};

inline Render render(const MaterialScene& scene, Backend backend, const CameraSpec& camera,
                     Extent extent, int samples, const RenderSettings& settings = {},
                     const MaterialOptions& options = {}, unsigned first_sample = 0) {
  MaterialRenderer renderer(scene, backend, options);
  renderer.restart(camera, extent, first_sample);
  renderer.add_samples(settings, samples);
  return {renderer.sums(), renderer.mean_radiance(), renderer.non_finite()};
}

// The furnace's camera narrowed to the middle of the sphere: every pixel sees it nearly
// head-on (cos theta above 0.997).
inline CameraSpec sphere_centre_camera() {
  CameraSpec camera = sphere_camera();
  camera.fov_degrees = 2.0;
  return camera;
}

// The root mean square difference of two images, over pixels and channels.
inline double rms(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
  return rms_difference(a, b);
}

} // namespace rt::ch12::testing
