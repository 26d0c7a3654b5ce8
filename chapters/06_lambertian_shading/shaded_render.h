// Chapter 06: the shaded scene rendered on either backend, by a kernel specialised on the
// features the frame uses or by the all-features kernel; the float64 reference of the same
// code; and the measures the report prints.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "camera_spec.h"
#include "rt/backend.h"
#include "rt/device_buffer.h"
#include "rt/image.h"
#include "shaded_frame.h"
#include "shaded_scene.h"

namespace rt::ch06 {

enum class KernelKind { specialised, all_features };

const char* to_string(KernelKind kind);

// The arrays of a scene a kernel with `features` reads, in device memory and owned. Data
// a feature does not read (the normals, for flat shading) is not uploaded.
class DeviceShadedScene {
public:
  DeviceShadedScene(const ShadedScene& scene, unsigned features);
  SceneView view() const;
  std::size_t bytes_uploaded() const;

private:
  DeviceBuffer<Vec3f> vertices_;
  DeviceBuffer<IndexedTriangle> triangles_;
  DeviceBuffer<std::uint8_t> material_;
  DeviceBuffer<Vec3f> normals_;
  DeviceBuffer<IndexedTriangle> normal_indices_; // empty: the triangles index the normals
  Palette palette_;
  Lights lights_;
  bool lift_shadow_origins_;
};

// The features a kernel must be given the data of: its own set, or all of them.
inline unsigned uploaded_features(KernelKind kind, unsigned features) {
  return kind == KernelKind::specialised ? features : k_all_features;
}

// Renders a frame of `scene` (device pointers on the GPU backend, host pointers on the CPU)
// into pixels and, if not null, records and each pixel's linear colour (radiance, for .pfm
// and .exr files), all in the backend's memory. `features` is what the frame uses; `scene`
// must hold the arrays those features read.
void render_shaded(Backend backend, KernelKind kind, unsigned features, const SceneView& scene,
                   const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                   ShadedPixelRecord* records = nullptr, Vec3f* radiance = nullptr);

// Registers per thread of the GPU kernel (cudaFuncGetAttributes); needs a usable GPU.
int kernel_registers(KernelKind kind, unsigned features);

// The float64 reference: the same code in double on the float camera's rays (CPU).
struct ShadedReference {
  Image image;
  long long rays = 0; // primary and shadow rays traced
};
ShadedReference render_shaded_reference(const ShadedScene& scene, unsigned features,
                                        const CameraSpec& camera, Extent extent);

struct ShadedFrameError {
  long long pixels_differing = 0; // any channel differs
  double rmse = 0.0;              // of the 8-bit R, G, B values, over every pixel
  long long nan_pixels = 0;
  long long shadow_rays = 0;     // traced in the frame
  long long shadowed_facing = 0; // shadow rays blocked where the face faces the light
};
ShadedFrameError compare_with_reference(const Image& image,
                                        const std::vector<ShadedPixelRecord>& records,
                                        const Image& reference);

} // namespace rt::ch06
