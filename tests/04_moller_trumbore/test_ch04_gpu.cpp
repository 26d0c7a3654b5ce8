// Chapter 04 tests on the GPU, built with nvcc's default flags (FMA contraction on): closest
// hits equal the CPU's, and the watertight test still never leaks.
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "rt_catch.h"

#include "adversarial_rays.h"
#include "gpu_guard.h"
#include "leak_configurations.h"
#include "mesh_render.h"
#include "rt/device_buffer.h"
#include "triangle_cases.h"
#include "triangles.h"

using namespace rt;
using namespace rt::ch04;

namespace {

// Rays from inside in uniformly random directions: almost none passes within an ulp of an
// edge, so both backends must agree on every hit.
std::vector<RayF> random_rays_from(Vec3f inside, float spread, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<RayF> rays;
  while (static_cast<int>(rays.size()) < count) {
    const Vec3f jitter{unit(rng), unit(rng), unit(rng)};
    const Vec3f direction{unit(rng), unit(rng), unit(rng)};
    if (!(length_squared(jitter) <= 1.0f && length_squared(direction) > 0.01f)) continue;
    rays.push_back(RayF{inside + jitter * spread, direction});
  }
  return rays;
}

// GPU and CPU closest hits that disagree: a different hit or miss, or a different triangle
// whose t is not a tie (t within 8 ulps: two triangles meeting where the ray passes, whose t
// FMA contraction rounds differently on the GPU).
long long count_disagreements(const std::vector<MeshHit>& gpu,
                              const std::vector<MeshHit>& cpu) {
  constexpr float k_tie = 8 * std::numeric_limits<float>::epsilon();
  long long disagreements = 0;
  for (std::size_t i = 0; i < gpu.size(); ++i) {
    const bool gpu_hit = gpu[i].triangle >= 0, cpu_hit = cpu[i].triangle >= 0;
    if (gpu_hit != cpu_hit || std::isnan(gpu[i].t)) {
      ++disagreements;
    } else if (gpu_hit && !(std::abs(gpu[i].t - cpu[i].t) <= k_tie * cpu[i].t)) {
      ++disagreements;
    }
  }
  return disagreements;
}

} // namespace

TEST_CASE("GPU closest hits equal the CPU's for random rays from inside", "[ch04][gpu]") {
  RT_REQUIRE_GPU();
  for (const auto& configuration : k_leak_configurations) {
    const Mesh mesh = configuration.make_mesh();
    const std::vector<RayF> rays =
        random_rays_from(configuration.inside(), configuration.spread, 100'000, 7);
    for (const TriangleVariant variant : k_variants) {
      CAPTURE(configuration.name, to_string(variant));
      const auto gpu = closest_hits_gpu(variant, mesh, rays);
      const auto cpu = closest_hits_cpu(variant, mesh, rays);
      REQUIRE(gpu.size() == rays.size());
      CHECK(count_disagreements(gpu, cpu) == 0);
    }
  }
}

TEST_CASE("GPU watertight closest hits equal the CPU's for adversarial rays", "[ch04][gpu]") {
  RT_REQUIRE_GPU();
  // The edge functions, the shear and v - o are rounded explicitly, so they are the same
  // bits on both backends: every hit or miss agrees, only t may round differently.
  for (const auto& configuration : k_leak_configurations) {
    const Mesh mesh = configuration.make_mesh();
    const std::vector<RayF> rays = rays_at_vertices_and_edges(
        mesh, configuration.inside(), configuration.spread, 100'000, configuration.seed);
    CAPTURE(configuration.name);
    const auto gpu = closest_hits_gpu(TriangleVariant::watertight, mesh, rays);
    const auto cpu = closest_hits_cpu(TriangleVariant::watertight, mesh, rays);
    CHECK(count_disagreements(gpu, cpu) == 0);
  }
}

TEST_CASE("GPU watertight test never leaks with nvcc's default FMA contraction",
          "[ch04][gpu]") {
  RT_REQUIRE_GPU();
  constexpr int k_rays = 1'000'000;
  for (const auto& configuration : k_leak_configurations) {
    const Mesh mesh = configuration.make_mesh();
    const std::vector<RayF> rays = rays_at_vertices_and_edges(
        mesh, configuration.inside(), configuration.spread, k_rays, configuration.seed);
    for (const TriangleVariant variant : k_variants) {
      const LeakCount count = count_leaks_gpu(variant, mesh, rays);
      std::printf("GPU %-24s %-16s %lld rays: %lld leaks, %lld double hits\n",
                  configuration.name, to_string(variant), count.rays, count.leaks,
                  count.double_hits);
      CAPTURE(configuration.name, to_string(variant), count.leaks, count.double_hits);
      CHECK(count.non_finite == 0);
      CHECK(count.rays == k_rays);
      if (variant == TriangleVariant::watertight) CHECK(count.leaks == 0);
    }
  }
}

TEST_CASE("GPU render of the demo scene equals the CPU's, with no holes", "[ch04][gpu]") {
  RT_REQUIRE_GPU();
  const Extent extent{320, 180};
  const ch04::TriangleScene scene = ch04::make_demo_scene(2, {0, 0, 0});
  const ch03::CameraSpec spec = rt::testing::demo_scene_camera();
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  const ch04::MeshReference reference = ch04::render_triangles_reference(scene, spec, extent);
  const ch04::DeviceTriangleScene d_scene(scene);
  for (TriangleVariant variant : k_variants) {
    Image gpu(extent.width, extent.height), cpu(extent.width, extent.height);
    std::vector<ch04::MeshPixelRecord> records(gpu.pixels.size());
    DeviceBuffer<Rgba8> d_pixels(gpu.pixels.size());
    DeviceBuffer<ch04::MeshPixelRecord> d_records(records.size());
    ch04::render_triangles(Backend::gpu, variant, d_scene.view(), d_scene.object(), camera,
                           extent, d_pixels.data(), d_records.data());
    d_pixels.download(gpu.pixels);
    d_records.download(records);
    ch04::render_triangles(Backend::cpu, variant, ch04::host_view(scene.mesh),
                           scene.object.data(), camera, extent, cpu.pixels.data());
    const ch04::MeshFrameError e = ch04::compare_with_reference(gpu, records, reference);
    CAPTURE(ch04::to_string(variant), e.pixels_differing, e.holes);
    CHECK(static_cast<long long>(count_differing_pixels(gpu.pixels, cpu.pixels)) <=
          extent.pixel_count() / 200);
    CHECK(e.nan_pixels == 0);
    if (variant == TriangleVariant::watertight) CHECK(e.holes == 0);
  }
}
