// Chapter 11: the megakernel, the tone map and the progressive renderer. See path_render.h.
#include "path_render.h"

#include <cmath>

#include "collapse.h"
#include "path_dispatch.h"
#include "rt/backend_image.h"
#include "rt/cuda_check.h"
#include "rt/error.h"
#include "wavefront.h"

namespace rt::ch11 {

const char* to_string(PathVariant variant) {
  return variant == PathVariant::megakernel ? "megakernel" : "wavefront";
}

const char* to_string(Strategy strategy) {
  switch (strategy) {
  case Strategy::bsdf:
    return "bsdf";
  case Strategy::light:
    return "light";
  case Strategy::mis:
    return "mis";
  }
  return "?";
}

PathVariant parse_variant(const std::string& text) {
  if (text == "megakernel") return PathVariant::megakernel;
  if (text == "wavefront") return PathVariant::wavefront;
  throw UsageError("unknown variant '" + text + "' (megakernel or wavefront)");
}

Strategy parse_strategy(const std::string& text) {
  if (text == "bsdf") return Strategy::bsdf;
  if (text == "light") return Strategy::light;
  if (text == "mis") return Strategy::mis;
  throw UsageError("unknown strategy '" + text + "' (bsdf, light or mis)");
}

unsigned features_used(const PathScene& scene) {
  const Environment& e = scene.environment;
  unsigned features = 0;
  if (!scene.lights.triangles.empty()) features |= k_emitters;
  if (max_component(e.sky) > 0.0f) features |= k_sky;
  if (max_component(e.sun_irradiance) > 0.0f) features |= k_sun;
  return features;
}

std::string describe_path_features(unsigned features) {
  std::string text;
  const auto add = [&](unsigned feature, const char* name) {
    if ((features & feature) != 0) text += text.empty() ? name : std::string(", ") + name;
  };
  add(k_emitters, "emitters");
  add(k_sky, "sky");
  add(k_sun, "sun");
  return text.empty() ? "none" : text;
}

namespace {

// [listing:megakernel_pixel]
// One pixel of the megakernel: its samples one after another, each added to the running sum.
template <class F> struct MegakernelPixel {
  PathSceneView scene;
  F features;
  Strategy strategy;
  ch03::Camera<float> camera;
  unsigned first_sample;
  int samples;
  float4* sums;
  unsigned* non_finite;

  RT_HD void operator()(int x, int y) const {
    const int index = y * camera.pinhole.width + x;
    float4 sum = sums[index];
    for (int s = 0; s < samples; ++s)
      add_sample(
          sum, trace_path(scene, features, strategy, camera, x, y, first_sample + unsigned(s)),
          non_finite);
    sums[index] = sum;
  }
};
// [/listing:megakernel_pixel]

RT_HD inline float filmic(float x) { // Narkowicz 2015's fit of the ACES curve
  const float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
  return clamp_to(y, 0.0f, 1.0f);
}

RT_HD inline std::uint8_t srgb8(float linear) {
  const float v =
      linear <= 0.0031308f ? 12.92f * linear : 1.055f * powf(linear, 1.0f / 2.4f) - 0.055f;
  return static_cast<std::uint8_t>(clamp_to(v, 0.0f, 1.0f) * 255.0f + 0.5f);
}

struct ToneMapPixel {
  const float4* sums;
  Extent extent;
  float exposure;
  Rgba8* pixels;

  RT_HD void operator()(int x, int y) const {
    const int index = y * extent.width + x;
    const float4 s = sums[index];
    const float scale = s.w > 0.0f ? exposure / s.w : 0.0f;
    pixels[index] = {srgb8(filmic(s.x * scale)), srgb8(filmic(s.y * scale)),
                     srgb8(filmic(s.z * scale)), 255};
  }
};

} // namespace

void accumulate_megakernel(Backend backend, KernelKind kernel, unsigned features,
                           Strategy strategy, const PathSceneView& scene,
                           const ch03::Camera<float>& camera, unsigned first_sample,
                           int samples, float4* sums, unsigned* non_finite) {
  const Extent extent{camera.pinhole.width, camera.pinhole.height};
  with_kernel(kernel, features, [&](auto f) {
    using F = decltype(f);
    for_each_pixel(backend, extent,
                   MegakernelPixel<F>{scene, f, strategy, camera, first_sample, samples, sums,
                                      non_finite});
  });
}

int megakernel_registers(KernelKind kernel, unsigned features) {
  int registers = 0;
  with_kernel(kernel, features, [&](auto f) {
    cudaFuncAttributes attributes{};
    RT_CUDA_CHECK(cudaFuncGetAttributes(&attributes,
                                        for_each_pixel_kernel<MegakernelPixel<decltype(f)>>));
    registers = attributes.numRegs;
  });
  return registers;
}

void tone_map(Backend backend, const float4* sums, Extent extent, float exposure,
              Rgba8* pixels) {
  for_each_pixel(backend, extent, ToneMapPixel{sums, extent, exposure, pixels});
}

// The scene's arrays in device memory.
struct DevicePathScene {
  ch09::DeviceWideTree<ch09::WideNode<4>, ch09::PackedTriangles> tree;
  DeviceBuffer<Vec3f> vertices;
  DeviceBuffer<ch04::IndexedTriangle> triangles;
  DeviceBuffer<int> material;
  DeviceBuffer<PathMaterial> materials;
  DeviceBuffer<int> light_triangles;
  DeviceBuffer<float> light_cdf;
};

namespace {

PathSceneView make_view(const PathScene& scene, PathTree::View tree, const Vec3f* vertices,
                        const ch04::IndexedTriangle* triangles, const int* material,
                        const PathMaterial* materials, const int* light_triangles,
                        const float* light_cdf) {
  return {tree,
          {vertices, triangles, static_cast<int>(scene.mesh.triangles.size())},
          material,
          materials,
          light_triangles,
          light_cdf,
          static_cast<int>(scene.lights.triangles.size()),
          static_cast<float>(scene.lights.power),
          scene.environment};
}

} // namespace

PathRenderer::PathRenderer(const PathScene& scene, Backend backend)
    : scene_(scene), backend_(backend), features_(features_used(scene)),
      tree_(build_path_tree(scene.mesh)) {
  const PathScene& s = scene_;
  if (backend_ == Backend::gpu) {
    device_ = std::make_unique<DevicePathScene>(
        DevicePathScene{ch09::DeviceWideTree<ch09::WideNode<4>, ch09::PackedTriangles>(tree_),
                        DeviceBuffer<Vec3f>(std::span<const Vec3f>(s.mesh.vertices)),
                        DeviceBuffer<ch04::IndexedTriangle>(
                            std::span<const ch04::IndexedTriangle>(s.mesh.triangles)),
                        DeviceBuffer<int>(std::span<const int>(s.material)),
                        DeviceBuffer<PathMaterial>(std::span<const PathMaterial>(s.materials)),
                        DeviceBuffer<int>(std::span<const int>(s.lights.triangles)),
                        DeviceBuffer<float>(std::span<const float>(s.lights.cdf))});
    const DevicePathScene& d = *device_;
    view_ =
        make_view(s, d.tree.view(), d.vertices.data(), d.triangles.data(), d.material.data(),
                  d.materials.data(), d.light_triangles.data(), d.light_cdf.data());
  } else {
    view_ = make_view(s, tree_.view(), s.mesh.vertices.data(), s.mesh.triangles.data(),
                      s.material.data(), s.materials.data(), s.lights.triangles.data(),
                      s.lights.cdf.data());
  }
  non_finite_ = BackendArray<unsigned>(backend_, 1);
}

PathRenderer::~PathRenderer() = default;

void PathRenderer::restart(const CameraSpec& camera, Extent extent, unsigned first_sample) {
  camera_ = ch03::make_camera<float>(camera, extent);
  if (extent.width != extent_.width || extent.height != extent_.height) {
    sums_ = BackendArray<float4>(backend_, static_cast<std::size_t>(extent.pixel_count()));
    queues_.reset();
  }
  extent_ = extent;
  sums_.clear();
  non_finite_.clear();
  first_sample_ = first_sample;
  samples_ = 0;
}

void PathRenderer::add_samples(const RenderSettings& settings, int samples) {
  if (extent_.pixel_count() == 0) throw Error("PathRenderer: restart() before add_samples()");
  const unsigned first = first_sample_ + unsigned(samples_);
  if (settings.variant == PathVariant::megakernel) {
    accumulate_megakernel(backend_, settings.kernel, features_, settings.strategy, view_,
                          camera_, first, samples, sums_.data(), non_finite_.data());
  } else {
    if (!queues_) queues_ = std::make_unique<WavefrontQueues>(backend_, extent_.pixel_count());
    accumulate_wavefront(backend_, settings.kernel, features_, settings.strategy, view_,
                         camera_, first, samples, sums_.data(), non_finite_.data(), *queues_);
  }
  samples_ += samples;
}

RayCounts PathRenderer::add_counted_sample(Strategy strategy) {
  if (extent_.pixel_count() == 0) throw Error("PathRenderer: restart() before counting rays");
  if (!queues_) queues_ = std::make_unique<WavefrontQueues>(backend_, extent_.pixel_count());
  const WavefrontPass pass = accumulate_wavefront(
      backend_, KernelKind::specialised, features_, strategy, view_, camera_,
      first_sample_ + unsigned(samples_), 1, sums_.data(), non_finite_.data(), *queues_, true);
  samples_ += 1;
  return {pass.extended, pass.shadow_rays};
}

void PathRenderer::synchronize() const {
  if (backend_ == Backend::gpu) RT_CUDA_CHECK(cudaDeviceSynchronize());
}

std::vector<float4> PathRenderer::sums() const { return sums_.to_host(); }

std::vector<Vec3f> PathRenderer::mean_radiance() const {
  std::vector<Vec3f> mean;
  for (const float4& s : sums()) {
    const float scale = s.w > 0.0f ? 1.0f / s.w : 0.0f;
    mean.push_back({s.x * scale, s.y * scale, s.z * scale});
  }
  return mean;
}

Image PathRenderer::image(float exposure) const {
  return render_into_image(backend_, extent_,
                           [&](Rgba8* pixels) { tone_map_into(pixels, exposure); });
}

void PathRenderer::tone_map_into(Rgba8* pixels, float exposure) const {
  tone_map(backend_, sums_.data(), extent_, exposure, pixels);
}

unsigned long long PathRenderer::non_finite() const { return non_finite_.to_host()[0]; }

} // namespace rt::ch11
