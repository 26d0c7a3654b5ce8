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
#include "path_kernels.cuh"
#include "rt/backend_image.h"
#include "rt/cuda_check.h"
#include "rt/error.h"
#include "rt/kernel_info.h"
#include "wavefront_stages.cuh"
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

const char* to_string(SamplerKind sampler) {
  switch (sampler) {
  case SamplerKind::independent:
    return "independent";
  case SamplerKind::stratified:
    return "stratified";
  case SamplerKind::sobol:
    return "sobol";
  case SamplerKind::zsobol:
    return "zsobol";
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

SamplerKind parse_sampler(const std::string& text) {
  for (const SamplerKind kind : k_samplers)
    if (text == to_string(kind)) return kind;
  throw UsageError("unknown sampler '" + text + "' (independent, stratified, sobol or zsobol)");
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
          scene.environment,
          Sampler{}}; // set for each pass (accumulate)
}

} // namespace

namespace {

PathTree build_tree(TreeBuild build, Backend backend, const ch04::Mesh& mesh) {
  if (build == TreeBuild::sah) return build_path_tree(mesh);
  return ch10::collapse_to_wide4(backend,
                                 ch10::build_lbvh(backend, mesh, ch10::CodeWidth::bits30).bvh);
}

} // namespace

ProgressiveRenderer::ProgressiveRenderer(Backend backend, unsigned features)
    : backend_(backend), features_(features), non_finite_(backend, 1), next_path_(backend, 1) {}

ProgressiveRenderer::~ProgressiveRenderer() = default;

void ProgressiveRenderer::restart(const CameraSpec& camera, Extent extent,
                                  unsigned first_sample) {
  camera_ = ch03::make_camera<float>(camera, extent);
  if (extent.width != extent_.width || extent.height != extent_.height) {
    sums_ = BackendArray<float4>(backend_, static_cast<std::size_t>(extent.pixel_count()));
    resized();
  }
  extent_ = extent;
  sums_.clear();
  non_finite_.clear();
  first_sample_ = first_sample;
  samples_ = 0;
}

Sampler ProgressiveRenderer::sampler_for(const RenderSettings& settings) const {
  return make_sampler(settings.sampler, extent_, settings.sampler_samples);
}

void ProgressiveRenderer::empty_sums() {
  sums_.clear();
  non_finite_.clear();
  samples_ = 0;
}

WavefrontPass ProgressiveRenderer::add_samples(const RenderSettings& settings, int samples) {
  if (extent_.pixel_count() == 0) throw Error("renderer: restart() before add_samples()");
  const WavefrontPass pass =
      accumulate(settings, first_sample_ + unsigned(samples_), samples, false);
  samples_ += samples;
  return pass;
}

RayCounts ProgressiveRenderer::add_counted_sample(Strategy strategy) {
  if (extent_.pixel_count() == 0) throw Error("renderer: restart() before counting rays");
  const WavefrontPass pass =
      accumulate({PathVariant::wavefront, KernelKind::specialised, strategy},
                 first_sample_ + unsigned(samples_), 1, true);
  samples_ += 1;
  return {pass.extended, pass.shadow_rays};
}

void ProgressiveRenderer::synchronize() const {
  if (backend_ == Backend::gpu) RT_CUDA_CHECK(cudaDeviceSynchronize());
}

std::vector<float4> ProgressiveRenderer::sums() const { return sums_.to_host(); }

std::vector<Vec3f> ProgressiveRenderer::mean_radiance() const {
  std::vector<Vec3f> mean;
  for (const float4& s : sums()) {
    const float scale = s.w > 0.0f ? 1.0f / s.w : 0.0f;
    mean.push_back({s.x * scale, s.y * scale, s.z * scale});
  }
  return mean;
}

Image ProgressiveRenderer::image(float exposure) const {
  return render_into_image(backend_, extent_,
                           [&](Rgba8* pixels) { tone_map_into(pixels, exposure); });
}

void ProgressiveRenderer::tone_map_into(Rgba8* pixels, float exposure) const {
  tone_map(backend_, sums_.data(), extent_, exposure, pixels);
}

unsigned long long ProgressiveRenderer::non_finite() const { return non_finite_.to_host()[0]; }

PathRenderer::PathRenderer(const PathScene& scene, Backend backend, TreeBuild build)
    : ProgressiveRenderer(backend, features_used(scene)), scene_(scene), build_(build),
      tree_(build_tree(build, backend, scene.mesh)) {
  upload();
}

PathRenderer::PathRenderer(Backend backend, unsigned features)
    : ProgressiveRenderer(backend, features) {}

void PathRenderer::move_vertices(const std::vector<Vec3f>& vertices) {
  if (vertices.size() != scene_.mesh.vertices.size())
    throw InputError("move_vertices: " + std::to_string(vertices.size()) +
                     " vertices for a scene of " + std::to_string(scene_.mesh.vertices.size()));
  scene_.mesh.vertices = vertices;
  scene_.lights = build_light_table(scene_);
  tree_ = build_tree(build_, backend_, scene_.mesh);
  upload();
  empty_sums();
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

void PathRenderer::resized() { queues_.reset(); }

WavefrontPass PathRenderer::accumulate(const RenderSettings& settings, unsigned first,
                                       int samples, bool count_rays) {
  WavefrontPass pass;
  view_.sampler = sampler_for(settings);
  with_kernel(settings.kernel, features_, [&](auto f) {
    if (settings.variant == PathVariant::megakernel) {
      run_megakernel(backend_, f, settings.strategy, view_, camera_, first, samples,
                     sums_.data(), non_finite_.data());
    } else if (settings.variant == PathVariant::persistent) {
      run_persistent(backend_, f, settings.strategy, view_, camera_, first, samples,
                     sums_.data(), non_finite_.data(), next_path_.data());
    } else {
      if (!queues_)
        queues_ = std::make_unique<WavefrontQueues>(backend_, extent_.pixel_count());
      pass = run_wavefront(backend_, f, settings.strategy, view_, camera_, first, samples,
                           sums_.data(), non_finite_.data(), *queues_, count_rays);
    }
  });
  return pass;
}

int PathRenderer::registers(const RenderSettings& settings) const {
  int registers = 0;
  with_kernel(settings.kernel, features_, [&](auto f) {
    using F = decltype(f);
    registers = settings.variant == PathVariant::wavefront
                    ? wavefront_registers_of<PathSceneView, F>()
                    : megakernel_registers_of<PathSceneView, F>(settings.variant ==
                                                                PathVariant::persistent);
  });
  return registers;
}

} // namespace rt::ch11
