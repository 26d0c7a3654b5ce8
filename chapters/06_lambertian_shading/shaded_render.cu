// Chapter 06: rendering the shaded scene. See shaded_render.h.
#include "shaded_render.h"

#include <atomic>
#include <cmath>
#include <span>

#include "rt/cuda_check.h"
#include "rt/error.h"
#include "rt/kernel_info.h"
#include "rt/launch.h"

namespace rt::ch06 {
namespace {

using FrameLaunch = FrameLaunchOf<SceneView>;

// [listing:shade_kernel]
// The chapter's own kernel rather than chapter 01's for_each_pixel: its address, one per
// feature set, is what rt::kernel_registers (rt/kernel_info.h) needs to report registers per
// thread.
template <class F> __global__ void shade_kernel(FrameLaunch frame, F features) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x;
  const int y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x < frame.extent.width && y < frame.extent.height) shade_pixel(frame, features, x, y);
}

template <class F> int registers_of() { return rt::kernel_registers(shade_kernel<F>); }
// [/listing:shade_kernel]

template <class F> void render_with(Backend backend, const FrameLaunch& frame, F features) {
  if (backend == Backend::cpu) {
    for_each_pixel_cpu(frame.extent, [&](int x, int y) { shade_pixel(frame, features, x, y); });
    return;
  }
  if (backend != Backend::gpu) throw Error("render_shaded: resolve the backend first");
  if (frame.extent.width <= 0 || frame.extent.height <= 0) return;
  const BlockShape block;
  const dim3 threads(block.x, block.y);
  const dim3 grid(blocks_to_cover(frame.extent.width, block.x),
                  blocks_to_cover(frame.extent.height, block.y));
  shade_kernel<<<grid, threads>>>(frame, features);
  RT_CUDA_CHECK_LAUNCH("shade_kernel");
}

// Every Rgba8 of the two images: the squared differences of R, G and B summed.
double squared_error(const Rgba8& a, const Rgba8& b) {
  const double r = double(a.r) - b.r, g = double(a.g) - b.g, bl = double(a.b) - b.b;
  return r * r + g * g + bl * bl;
}

} // namespace

const char* to_string(KernelKind kind) {
  return kind == KernelKind::specialised ? "specialised" : "all-features";
}

DeviceShadedScene::DeviceShadedScene(const ShadedScene& scene, unsigned features)
    : vertices_(std::span<const Vec3f>(scene.mesh.vertices)),
      triangles_(std::span<const IndexedTriangle>(scene.mesh.triangles)),
      material_(std::span<const std::uint8_t>(scene.material)), palette_(scene.palette),
      lights_(scene.lights), lift_shadow_origins_(scene.lift_shadow_origins) {
  if ((features & k_smooth_normals) == 0) return; // flat shading reads no vertex normals
  normals_ = DeviceBuffer<Vec3f>(std::span<const Vec3f>(scene.normals));
  normal_indices_ =
      DeviceBuffer<IndexedTriangle>(std::span<const IndexedTriangle>(scene.normal_indices));
}

SceneView DeviceShadedScene::view() const {
  SceneView view{{vertices_.data(), triangles_.data(), static_cast<int>(triangles_.size())},
                 material_.data(),
                 nullptr,
                 nullptr,
                 palette_,
                 lights_,
                 lift_shadow_origins_};
  if (normals_.size() > 0) {
    view.normals = normals_.data();
    view.normal_indices =
        normal_indices_.size() > 0 ? normal_indices_.data() : triangles_.data();
  }
  return view;
}

std::size_t DeviceShadedScene::bytes_uploaded() const {
  return vertices_.bytes() + triangles_.bytes() + material_.bytes() + normals_.bytes() +
         normal_indices_.bytes();
}

// [listing:render_shaded]
void render_shaded(Backend backend, KernelKind kind, unsigned features, const SceneView& scene,
                   const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                   ShadedPixelRecord* records, Vec3f* radiance) {
  const FrameLaunch frame{scene, camera, extent, pixels, records, radiance};
  if (kind == KernelKind::all_features)
    return render_with(backend, frame, AllFeatures{features});
  with_specialised(features,
                   [&](auto specialised) { render_with(backend, frame, specialised); });
}
// [/listing:render_shaded]

int kernel_registers(KernelKind kind, unsigned features) {
  if (kind == KernelKind::all_features) return registers_of<AllFeatures>();
  return with_specialised(
      features, [](auto specialised) { return registers_of<decltype(specialised)>(); });
}

ShadedReference render_shaded_reference(const ShadedScene& scene, unsigned features,
                                        const CameraSpec& spec, Extent extent) {
  const SceneView view = host_view(scene, k_all_features);
  const ch03::FloatRaysInDouble camera{ch03::make_camera<float>(spec, extent)};
  ShadedReference reference{Image(extent.width, extent.height), extent.pixel_count()};
  std::atomic<long long> shadow_rays{0};
  for_each_pixel_cpu(extent, [&](int x, int y) {
    const ShadedSample<double> sample =
        shade_ray(view, camera.ray_through_pixel(x, y), AllFeatures{features});
    reference.image.at(x, y) = ch03::to_rgba8(sample.colour);
    shadow_rays.fetch_add(sample.shadow_rays, std::memory_order_relaxed);
  });
  reference.rays += shadow_rays.load();
  return reference;
}

ShadedFrameError compare_with_reference(const Image& image,
                                        const std::vector<ShadedPixelRecord>& records,
                                        const Image& reference) {
  if (image.pixels.size() != reference.pixels.size() || records.size() != image.pixels.size())
    throw Error("compare_with_reference: the frame and its reference differ in size");
  ShadedFrameError error;
  error.pixels_differing =
      static_cast<long long>(count_differing_pixels(image.pixels, reference.pixels));
  double sum = 0.0;
  for (std::size_t i = 0; i < records.size(); ++i) {
    sum += squared_error(image.pixels[i], reference.pixels[i]);
    error.nan_pixels += records[i].nan;
    error.shadow_rays += records[i].shadow_rays;
    error.shadowed_facing += records[i].shadowed_facing;
  }
  error.rmse = records.empty() ? 0.0 : std::sqrt(sum / (3.0 * double(records.size())));
  return error;
}

} // namespace rt::ch06
