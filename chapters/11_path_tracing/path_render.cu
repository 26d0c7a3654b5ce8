// Chapter 11: the megakernel, the tone map and the progressive renderer. See path_render.h.
// Compiled with -fmad=false (CMakeLists.txt), as chapter 07's protocol_gpu.cu is: no a * b + c
// is fused on the GPU, as none is on the CPU, so both backends trace the same paths bit for
// bit.
#define RT_NO_CONTRACTION 1
#include "path_render.h"

#include <cmath>

#include "collapse.h"
#include "gpu_build.h"
#include "path_dispatch.h"
#include "rt/backend_image.h"
#include "rt/cuda_check.h"
#include "rt/error.h"
#include "rt/kernel_info.h"
#include "wavefront.h"
#include "wide_collapse.h"

namespace rt::ch11 {

const char* to_string(PathVariant variant) {
  switch (variant) {
  case PathVariant::megakernel:
    return "megakernel";
  case PathVariant::persistent:
    return "persistent";
  case PathVariant::wavefront:
    return "wavefront";
  }
  return "?";
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
  if (text == "persistent") return PathVariant::persistent;
  if (text == "wavefront") return PathVariant::wavefront;
  throw UsageError("unknown variant '" + text + "' (megakernel, persistent or wavefront)");
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

// [listing:persistent_paths]
// The persistent megakernel (Aila & Laine 2009's persistent threads, with the path
// regeneration of Novak et al. 2010). In the megakernel a warp runs until the longest of its
// 32 paths ends, the lanes of the shorter ones idle; here a lane whose path ended takes the
// next one. The lanes that need a path take them together, one atomic per warp; paths are
// numbered in tiles of pixels, a warp's worth each, so that a warp's camera rays start
// coherent. One sample per launch: each pixel's sum gets one path, in sample order as in the
// megakernel.
constexpr unsigned k_warp_lanes = 32;
constexpr unsigned k_tile_width = 8, k_tile_height = 4; // pixels
static_assert(k_tile_width * k_tile_height == k_warp_lanes, "a tile is one warp's paths");

template <class F>
__global__ void persistent_paths_kernel(PathSceneView scene, F features, Strategy strategy,
                                        ch03::Camera<float> camera, unsigned sample,
                                        float4* sums, unsigned* non_finite,
                                        unsigned* next_path) {
  const int width = camera.pinhole.width, height = camera.pinhole.height;
  const unsigned tiles_x = (unsigned(width) + k_tile_width - 1) / k_tile_width;
  const unsigned tiles_y = (unsigned(height) + k_tile_height - 1) / k_tile_height;
  const unsigned paths = tiles_x * tiles_y * k_warp_lanes;
  const unsigned lane = threadIdx.x % k_warp_lanes;
  PathState path{};
  bool alive = false;
  for (;;) {
    const unsigned active = __activemask();
    const unsigned idle = __ballot_sync(active, !alive);
    if (idle != 0) {
      const int leader = __ffs(int(idle)) - 1;
      unsigned first = 0;
      if (int(lane) == leader) first = atomicAdd(next_path, unsigned(__popc(int(idle))));
      first = __shfl_sync(active, first, leader);
      if (!alive) {
        const unsigned index = first + unsigned(__popc(int(idle & ((1u << lane) - 1u))));
        if (index >= paths) break; // every path is taken
        const unsigned tile = index / k_warp_lanes, within = index % k_warp_lanes;
        const int x = int((tile % tiles_x) * k_tile_width + within % k_tile_width);
        const int y = int((tile / tiles_x) * k_tile_height + within / k_tile_width);
        if (x >= width || y >= height) continue; // a tile's part outside the image
        path = start_path(camera, x, y, sample);
        alive = true;
      }
    }
    alive = extend_path(scene, features, strategy, path);
    if (!alive) {
      float4 sum = sums[path.pixel];
      add_sample(sum, path.radiance, non_finite);
      sums[path.pixel] = sum;
    }
  }
}
// [/listing:persistent_paths]

// Blocks of the persistent kernel: as many as the GPU keeps resident at once.
constexpr int k_persistent_threads = 128;
template <class F> int persistent_blocks() {
  return resident_blocks(persistent_paths_kernel<F>, k_persistent_threads);
}

RT_HD inline float filmic(float x) { // Narkowicz 2015's fit of the ACES curve
  // The curve reaches 1 at x = 7.25. Far beyond, at 1.8e19, x * x overflows and inf / inf is
  // NaN, which clamps to black: the brightest pixels would come out darkest.
  if (!(x < 16.0f)) return 1.0f;
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

void accumulate_persistent(Backend backend, KernelKind kernel, unsigned features,
                           Strategy strategy, const PathSceneView& scene,
                           const ch03::Camera<float>& camera, unsigned first_sample,
                           int samples, float4* sums, unsigned* non_finite,
                           unsigned* next_path) {
  if (backend == Backend::cpu)
    return accumulate_megakernel(backend, kernel, features, strategy, scene, camera,
                                 first_sample, samples, sums, non_finite);
  with_kernel(kernel, features, [&](auto f) {
    using F = decltype(f);
    const int blocks = persistent_blocks<F>();
    for (int s = 0; s < samples; ++s) {
      RT_CUDA_CHECK(cudaMemsetAsync(next_path, 0, sizeof(unsigned)));
      persistent_paths_kernel<F><<<blocks, k_persistent_threads>>>(
          scene, f, strategy, camera, first_sample + unsigned(s), sums, non_finite, next_path);
      RT_CUDA_CHECK_LAUNCH("persistent_paths_kernel");
    }
  });
}

int megakernel_registers(KernelKind kernel, unsigned features, PathVariant variant) {
  int registers = 0;
  with_kernel(kernel, features, [&](auto f) {
    using F = decltype(f);
    registers = variant == PathVariant::persistent
                    ? kernel_registers(persistent_paths_kernel<F>)
                    : kernel_registers(for_each_pixel_kernel<MegakernelPixel<F>>);
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

namespace {

PathTree build_tree(TreeBuild build, Backend backend, const ch04::Mesh& mesh) {
  if (build == TreeBuild::sah) return build_path_tree(mesh);
  return ch10::collapse_to_wide4(backend,
                                 ch10::build_lbvh(backend, mesh, ch10::CodeWidth::bits30).bvh);
}

} // namespace

PathRenderer::PathRenderer(const PathScene& scene, Backend backend, TreeBuild build)
    : scene_(scene), backend_(backend), build_(build), features_(features_used(scene)),
      tree_(build_tree(build, backend, scene.mesh)) {
  upload();
  non_finite_ = BackendArray<unsigned>(backend_, 1);
  next_path_ = BackendArray<unsigned>(backend_, 1);
}

void PathRenderer::move_vertices(const std::vector<Vec3f>& vertices) {
  if (vertices.size() != scene_.mesh.vertices.size())
    throw InputError("move_vertices: " + std::to_string(vertices.size()) +
                     " vertices for a scene of " + std::to_string(scene_.mesh.vertices.size()));
  scene_.mesh.vertices = vertices;
  scene_.lights = build_light_table(scene_);
  tree_ = build_tree(build_, backend_, scene_.mesh);
  upload();
  sums_.clear();
  non_finite_.clear();
  samples_ = 0;
}

void PathRenderer::upload() {
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
  } else if (settings.variant == PathVariant::persistent) {
    accumulate_persistent(backend_, settings.kernel, features_, settings.strategy, view_,
                          camera_, first, samples, sums_.data(), non_finite_.data(),
                          next_path_.data());
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
