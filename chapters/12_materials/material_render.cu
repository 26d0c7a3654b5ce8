// Chapter 12: the renderer of scenes with materials. See material_render.h. Compiled with
// -fmad=false, as chapter 11's kernels are (CMakeLists.txt): the GPU traces the CPU's paths.
#define RT_NO_CONTRACTION 1
#include "material_render.h"

#include "path_kernels.cuh"
#include "rt/backend_array.h"
#include "rt/device_buffer.h"
#include "rt/error.h"
#include "rt/timer.h"
#include "wavefront_stages.cuh"
#include "wide_trace.h"

namespace rt::ch12 {

using ch06::KernelKind;

unsigned material_features_used(const MaterialScene& scene) {
  unsigned features = ch11::features_used(scene.path);
  for (const Material& m : scene.materials) {
    if (m.model != MaterialModel::lambertian) features |= k_specular;
    const bool textured =
        m.base_color_texture != k_no_texture || m.roughness_texture != k_no_texture ||
        m.metallic_texture != k_no_texture || m.emission_texture != k_no_texture;
    if (textured && !scene.uv.empty()) features |= k_textures;
  }
  return features;
}

std::string describe_material_features(unsigned features) {
  std::string text = ch11::describe_path_features(features & ch11::k_all_path_features);
  if (text == "none") text.clear();
  const auto add = [&](unsigned feature, const char* name) {
    if ((features & feature) != 0) text += text.empty() ? name : std::string(", ") + name;
  };
  add(k_textures, "textures");
  add(k_specular, "specular");
  return text.empty() ? "none" : text;
}

namespace {

// [listing:material_kernel]
// Chapter 12's kernels are specialised on what the materials need, textures and the specular
// BSDFs, each compiled in or left out; chapter 11's lights are compiled into every one and
// switched by the scene's flags (chapter 11 measured what specialising on them is worth).
template <unsigned kCompiled> struct MaterialKernel {
  unsigned flags = 0;
  RT_HD static constexpr bool compiled(unsigned feature) { return (kCompiled & feature) != 0; }
  RT_HD bool on(unsigned feature) const { return (flags & feature) != 0; }
};

template <class Launch>
void with_material_kernel(KernelKind kernel, unsigned features, Launch&& launch) {
  constexpr unsigned lights = ch11::k_all_path_features;
  if (kernel == KernelKind::all_features)
    return launch(MaterialKernel<k_all_material_features>{features});
  switch (features & (k_textures | k_specular)) {
  case 0:
    return launch(MaterialKernel<lights>{features});
  case k_textures:
    return launch(MaterialKernel<lights | k_textures>{features});
  case k_specular:
    return launch(MaterialKernel<lights | k_specular>{features});
  default:
    return launch(MaterialKernel<k_all_material_features>{features});
  }
}
// [/listing:material_kernel]

// The base colour at one pixel (render_base_colour).
struct BaseColourPixel {
  MaterialSceneView scene;
  ch03::Camera<float> camera;
  int samples;
  Vec3f* out;

  RT_HD void operator()(int x, int y) const {
    using Kernel = MaterialKernel<k_all_material_features>;
    const Kernel features{k_textures | k_specular};
    Vec3f sum{};
    for (int s = 0; s < samples; ++s) {
      const unsigned pixel = unsigned(y * camera.pinhole.width + x);
      const float jx =
          samples > 1 ? ch11::sample_number(pixel, unsigned(s), 0, 0) - 0.5f : 0.0f;
      const float jy =
          samples > 1 ? ch11::sample_number(pixel, unsigned(s), 0, 1) - 0.5f : 0.0f;
      const ch03::RayF ray = ch11::camera_ray_jittered(camera, x, y, jx, jy);
      const TraceHit hit = ch09::trace_wide<ch07::Query::closest>(scene.tree, ray);
      if (hit.triangle < 0) continue;
      const ch04::TriangleF t = scene.mesh.triangle(hit.triangle);
      const Vec3f p = ray.origin + ray.direction * hit.t;
      const RayCone cone = propagate({0.0f, scene.pixel_spread}, hit.t);
      const Vec3f n = ch11::front_normal(t, -ray.direction);
      const SurfaceAt surface =
          surface_at(scene, features, scene.surfaces[scene.material[hit.triangle]],
                     hit.triangle, t, p, cone, dot(n, ray.direction));
      sum += surface.bsdf.base_color;
    }
    out[y * camera.pinhole.width + x] = sum / float(samples);
  }
};

// [listing:visible_normal_timing]
// One thread's 64 visible normals (time_visible_normals): each from its own incident direction
// and roughness, hashed as the path tracer hashes its numbers.
constexpr int k_normals_per_thread = 64;
struct VisibleNormalThread {
  VisibleNormals sampler;
  float* sums;
  RT_HD void operator()(int i) const {
    float sum = 0.0f;
    for (int k = 0; k < k_normals_per_thread; ++k) {
      const auto number = [&](unsigned d) {
        return ch11::sample_number(unsigned(i), unsigned(k), 0, d);
      };
      const float cos_o = 1.0f - number(0), phi = number(1);
      const float sin_o = square_root(max_of(0.0f, 1.0f - cos_o * cos_o));
      const ch07::SinCos turn = ch07::sin_cos_turns(phi);
      const Vec3f wo{sin_o * turn.cos, sin_o * turn.sin, cos_o};
      const float alpha = 0.001f + 0.999f * number(2);
      const Vec3f m = sampler == VisibleNormals::heitz
                          ? sample_visible_normal_heitz(wo, alpha, number(3), number(4))
                          : sample_visible_normal_caps(wo, alpha, number(3), number(4));
      sum += m.z;
    }
    sums[i] = sum;
  }
};
// [/listing:visible_normal_timing]

} // namespace

VisibleNormalTiming time_visible_normals(Backend backend, VisibleNormals sampler, int threads,
                                         int frames) {
  BackendArray<float> sums(backend, static_cast<std::size_t>(threads));
  const VisibleNormalThread run{sampler, sums.data()};
  const Timing t = time_on(
      backend, [&] { for_each_index(backend, threads, run); }, frames);
  double total = 0.0;
  for (const float s : sums.to_host()) total += s;
  const long long samples = static_cast<long long>(threads) * k_normals_per_thread;
  return {t.median_ms, samples, total / double(samples)};
}

// The scene's arrays in device memory.
struct DeviceMaterialScene {
  ch09::DeviceWideTree<ch09::WideNode<4>, ch09::PackedTriangles> tree;
  DeviceBuffer<Vec3f> vertices;
  DeviceBuffer<ch04::IndexedTriangle> triangles;
  DeviceBuffer<int> material;
  DeviceBuffer<ch11::PathMaterial> path_materials;
  DeviceBuffer<Material> surfaces;
  DeviceBuffer<Vec2f> uv;
  DeviceBuffer<int> light_triangles;
  DeviceBuffer<float> light_cdf;
  DeviceBuffer<float> e, e_avg, dielectric; // the compensation tables
  DeviceTextures textures;
};

namespace {

template <class T> std::span<const T> span_of(const std::vector<T>& v) { return v; }

std::span<const Vec2f> uv_span(const MaterialScene& s) {
  return {reinterpret_cast<const Vec2f*>(s.uv.data()), s.uv.size() * 3};
}

} // namespace

MaterialRenderer::MaterialRenderer(const MaterialScene& scene, Backend backend,
                                   MaterialOptions options)
    : ProgressiveRenderer(backend, material_features_used(scene)), scene_(scene),
      options_(options), tree_(ch11::build_path_tree(scene.path.mesh)) {
  const ch11::PathScene& s = scene_.path;
  if (backend_ == Backend::gpu) {
    device_ = std::make_unique<DeviceMaterialScene>(DeviceMaterialScene{
        ch09::DeviceWideTree<ch09::WideNode<4>, ch09::PackedTriangles>(tree_),
        DeviceBuffer<Vec3f>(span_of(s.mesh.vertices)),
        DeviceBuffer<ch04::IndexedTriangle>(span_of(s.mesh.triangles)),
        DeviceBuffer<int>(span_of(s.material)),
        DeviceBuffer<ch11::PathMaterial>(span_of(s.materials)),
        DeviceBuffer<Material>(span_of(scene_.materials)), DeviceBuffer<Vec2f>(uv_span(scene_)),
        DeviceBuffer<int>(span_of(s.lights.triangles)),
        DeviceBuffer<float>(span_of(s.lights.cdf)),
        DeviceBuffer<float>(span_of(compensation_.e())),
        DeviceBuffer<float>(span_of(compensation_.e_avg())),
        DeviceBuffer<float>(span_of(compensation_.dielectric())),
        DeviceTextures(scene_.textures)});
  } else {
    host_textures_ = HostTextures(scene_.textures);
  }
  make_view();
}

MaterialRenderer::~MaterialRenderer() = default;

void MaterialRenderer::make_view() {
  const ch11::PathScene& s = scene_.path;
  MaterialSceneView v{};
  v.light_count = static_cast<int>(s.lights.triangles.size());
  v.light_power = static_cast<float>(s.lights.power);
  v.environment = s.environment;
  const int triangles = static_cast<int>(s.mesh.triangles.size());
  if (device_) {
    const DeviceMaterialScene& d = *device_;
    v.tree = d.tree.view();
    v.mesh = {d.vertices.data(), d.triangles.data(), triangles};
    v.material = d.material.data();
    v.materials = d.path_materials.data();
    v.light_triangles = d.light_triangles.data();
    v.light_cdf = d.light_cdf.data();
    v.surfaces = d.surfaces.data();
    v.uv = scene_.uv.empty() ? nullptr : d.uv.data();
    v.textures = d.textures.table(options_.filter, options_.texture_objects);
    v.compensation = {d.e.data(), d.e_avg.data(), d.dielectric.data(), options_.compensation};
  } else {
    v.tree = tree_.view();
    v.mesh = {s.mesh.vertices.data(), s.mesh.triangles.data(), triangles};
    v.material = s.material.data();
    v.materials = s.materials.data();
    v.light_triangles = s.lights.triangles.data();
    v.light_cdf = s.lights.cdf.data();
    v.surfaces = scene_.materials.data();
    v.uv = scene_.uv.empty() ? nullptr : uv_span(scene_).data();
    v.textures = host_textures_.table(options_.filter);
    v.compensation = compensation_.view(options_.compensation);
  }
  v.pixel_spread = view_.pixel_spread;
  view_ = v;
}

void MaterialRenderer::set_options(const MaterialOptions& options) {
  options_ = options;
  make_view();
  empty_sums();
}

std::string MaterialRenderer::describe_features() const {
  return describe_material_features(features_) + " (lights switched at run time)";
}

void MaterialRenderer::resized() { queues_.reset(); }

ch11::WavefrontPass MaterialRenderer::accumulate(const RenderSettings& settings, unsigned first,
                                                 int samples, bool count_rays) {
  view_.sampler = sampler_for(settings);
  view_.pixel_spread =
      camera_.kind == ch03::CameraKind::pinhole
          ? pinhole_spread_angle(camera_.pinhole.tan_half_vfov, camera_.pinhole.height)
          : 0.0f;
  ch11::WavefrontPass pass;
  with_material_kernel(settings.kernel, features_, [&](auto f) {
    if (settings.variant == PathVariant::megakernel) {
      ch11::run_megakernel(backend_, f, settings.strategy, view_, camera_, first, samples,
                           sums_.data(), non_finite_.data());
    } else if (settings.variant == PathVariant::persistent) {
      ch11::run_persistent(backend_, f, settings.strategy, view_, camera_, first, samples,
                           sums_.data(), non_finite_.data(), next_path_.data());
    } else {
      if (!queues_)
        queues_ = std::make_unique<ch11::BasicWavefrontQueues<MaterialPath>>(
            backend_, extent_.pixel_count());
      pass = ch11::run_wavefront(backend_, f, settings.strategy, view_, camera_, first, samples,
                                 sums_.data(), non_finite_.data(), *queues_, count_rays);
    }
  });
  return pass;
}

int MaterialRenderer::registers(const RenderSettings& settings) const {
  int registers = 0;
  with_material_kernel(settings.kernel, features_, [&](auto f) {
    using F = decltype(f);
    registers = settings.variant == PathVariant::wavefront
                    ? ch11::wavefront_registers_of<MaterialSceneView, F>()
                    : ch11::megakernel_registers_of<MaterialSceneView, F>(
                          settings.variant == PathVariant::persistent);
  });
  return registers;
}

std::vector<Vec3f> render_base_colour(const MaterialRenderer& renderer,
                                      const CameraSpec& camera, Extent extent, int samples) {
  const ch03::Camera<float> c = ch03::make_camera<float>(camera, extent);
  MaterialSceneView view = renderer.view();
  view.pixel_spread = c.kind == ch03::CameraKind::pinhole
                          ? pinhole_spread_angle(c.pinhole.tan_half_vfov, c.pinhole.height)
                          : 0.0f;
  BackendArray<Vec3f> out(renderer.backend(), static_cast<std::size_t>(extent.pixel_count()));
  for_each_pixel(renderer.backend(), extent, BaseColourPixel{view, c, samples, out.data()});
  return out.to_host();
}

} // namespace rt::ch12
