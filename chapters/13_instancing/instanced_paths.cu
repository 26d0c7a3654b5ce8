// Chapter 13: sky-lit paths through two levels. See instanced_paths.h.
// Compiled with -fmad=false (CMakeLists.txt), as chapter 11's kernels are, and with chapter
// 07's cosine sampling given its device side: no a * b + c is fused on the GPU, as none is on
// the CPU, so both backends trace the same paths bit for bit.
#define RT_NO_CONTRACTION 1
#include "instanced_paths.h"

#include "path_random.h"
#include "path_sampling.h"
#include "shade.h"
#include "spawn.h"
#include "trace.h"

namespace rt::ch13 {

namespace {

// [listing:instanced_path]
// One pixel's paths. At a hit the triangle is taken to the world by its instance (as the shaded
// frame does), its normal faced to the arriving ray; the next direction is chapter 11's
// cosine-weighted bounce, whose weight f cos / pdf is the albedo alone. From the fourth surface
// on a path survives with probability q = the largest channel of its throughput (at most
// 0.95) and is divided by q, which keeps the mean.
template <TopLayout kTop> struct TracePaths {
  TwoLevelView scene;
  ShadeView shade;
  ch03::Camera<float> camera;
  int width;
  PathSettings settings;
  Vec3f* radiance;
  Rgba8* pixels;
  RT_HD void operator()(int index) const {
    const int x = index % width, y = index / width;
    const unsigned pixel = static_cast<unsigned>(index);
    Vec3f sum{0.0f, 0.0f, 0.0f};
    for (int s = 0; s < settings.samples; ++s) {
      const unsigned sample = settings.first_sample + static_cast<unsigned>(s);
      RayF ray = camera.ray_through_pixel(x, y);
      Vec3f throughput{1.0f, 1.0f, 1.0f};
      for (unsigned vertex = 1;; ++vertex) {
        const InstanceHit hit = trace_two_level<Query::closest, kTop>(scene, ray);
        if (hit.instance < 0) {
          sum += throughput * settings.sky;
          break;
        }
        const Instance& instance = scene.instances[hit.instance];
        const ch04::TriangleF local = shade.meshes[instance.mesh].triangle(hit.triangle);
        const Affine& m = instance.to_world;
        const Vec3f a = m.point(local.v0), b = m.point(local.v1), c = m.point(local.v2);
        const Vec3f p = a * (1.0f - hit.u - hit.v) + b * hit.u + c * hit.v;
        const Vec3f n = ch06::faced(ch06::unit_or(cross(b - a, c - a), Vec3f{0.0f, 1.0f, 0.0f}),
                                    ray.direction * -1.0f);
        const Vec3f albedo =
            settings.white ? Vec3f{1.0f, 1.0f, 1.0f} : shade.albedo[hit.instance];
        throughput = throughput * albedo;
        if (vertex >= 4) {
          const float largest = max_component(throughput);
          const float q = largest < 0.95f ? largest : 0.95f;
          if (!(ch11::sample_number(pixel, sample, vertex, ch11::k_roulette) < q)) break;
          throughput = throughput / q;
        }
        const ch11::DirectionSample next =
            ch11::sample_cosine(n, ch11::sample_number(pixel, sample, vertex, ch11::k_bsdf_u),
                                ch11::sample_number(pixel, sample, vertex, ch11::k_bsdf_v));
        ray = RayF{ch03::offset_ray_origin(p, n), next.direction};
      }
    }
    const Vec3f mean = sum / float(settings.samples > 0 ? settings.samples : 1);
    radiance[index] = mean;
    if (pixels != nullptr) pixels[index] = ch03::to_rgba8(mean);
  }
};
// [/listing:instanced_path]

} // namespace

void render_paths(const TwoLevelScene& scene, const ch03::Camera<float>& camera, Extent extent,
                  const PathSettings& settings, Vec3f* radiance, Rgba8* pixels) {
  const int count = static_cast<int>(extent.pixel_count());
  with_top_layout(scene.top_layout(), [&](auto top) {
    for_each_index(scene.backend(), count,
                   TracePaths<decltype(top)::value>{scene.view(), scene.shade_view(), camera,
                                                    extent.width, settings, radiance, pixels});
  });
}

} // namespace rt::ch13
