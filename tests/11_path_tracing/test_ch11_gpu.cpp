// Chapter 11 tests on the GPU: the same sample numbers on both backends give nearly the same
// image (the backends' float arithmetic differs in the last bits: fused multiply-adds, sin
// and cos), the megakernel and wavefront agree on the GPU as on the CPU, and the persistent
// threads add exactly the megakernel's samples; a moved scene, its tree built on the GPU,
// renders as on the CPU.
#include <cmath>

#include "rt_catch.h"

#include "animation.h"
#include "gpu_guard.h"
#include "path_cases.h"

using namespace rt;
using namespace rt::ch11;
using namespace rt::ch11::testing;

namespace {

// The mean absolute difference over pixels and channels, relative to the image's mean.
double relative_difference(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
  double difference = 0.0, mean = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec3f d = a[i] - b[i];
    difference += std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    mean += a[i].x + a[i].y + a[i].z;
  }
  return difference / mean;
}

} // namespace

TEST_CASE("GPU and CPU render the same image up to float rounding", "[ch11][gpu]") {
  RT_REQUIRE_GPU();
  const PathScene room = load_path_scene(k_room);
  const Extent extent{64, 48};
  for (const PathVariant variant :
       {PathVariant::megakernel, PathVariant::persistent, PathVariant::wavefront}) {
    CAPTURE(to_string(variant));
    const RenderSettings settings{variant, KernelKind::specialised, Strategy::mis};
    unsigned long long gpu_bad = 1;
    const auto gpu =
        render_mean(room, Backend::gpu, cornell_camera(), extent, 8, settings, &gpu_bad);
    const auto cpu = render_mean(room, Backend::cpu, cornell_camera(), extent, 8, settings);
    CHECK(gpu_bad == 0);
    // Paths that round differently at one bounce part ways from there; most do not.
    CHECK(relative_difference(cpu, gpu) < 0.02);
  }
}

TEST_CASE("GPU: the megakernel and the wavefront agree", "[ch11][gpu]") {
  RT_REQUIRE_GPU();
  const PathScene room = load_path_scene(k_room);
  const Extent extent{64, 48};
  const auto mega = render_mean(room, Backend::gpu, cornell_camera(), extent, 8,
                                {PathVariant::megakernel, KernelKind::specialised});
  const auto wave = render_mean(room, Backend::gpu, cornell_camera(), extent, 8,
                                {PathVariant::wavefront, KernelKind::specialised});
  CHECK(relative_difference(mega, wave) < 0.02);
}

TEST_CASE("GPU: the persistent threads give the megakernel's sums, bit for bit",
          "[ch11][gpu]") {
  RT_REQUIRE_GPU();
  const PathScene room = load_path_scene(k_room);
  // A size that is no multiple of the 8x4 tiles, and several launches (one per sample).
  for (const Extent extent : {Extent{61, 43}, Extent{8, 4}, Extent{1, 1}}) {
    CAPTURE(extent.width, extent.height);
    const auto sums_of = [&](PathVariant variant) {
      PathRenderer renderer(room, Backend::gpu);
      renderer.restart(cornell_camera(), extent);
      renderer.add_samples({variant, KernelKind::specialised, Strategy::mis}, 5);
      return renderer.sums();
    };
    const std::vector<float4> persistent = sums_of(PathVariant::persistent);
    CHECK(same_sums(sums_of(PathVariant::megakernel), persistent));
    for (const float4& s : persistent) CHECK(s.w == 5.0f); // every pixel, every sample once
  }
}

TEST_CASE("GPU: a moved scene, its tree built on the GPU, renders as on the CPU",
          "[ch11][gpu]") {
  RT_REQUIRE_GPU();
  const PathScene start = lit_moving_scene(0.0, 24);
  const std::vector<Vec3f> later = lit_moving_scene(0.9, 24).mesh.vertices;
  const Extent extent{64, 48};
  const auto render = [&](Backend backend) {
    PathRenderer renderer(start, backend, TreeBuild::lbvh);
    renderer.restart(ch10::moving_scene_camera(), extent);
    renderer.move_vertices(later);
    renderer.add_samples({PathVariant::persistent, KernelKind::specialised, Strategy::mis}, 8);
    CHECK(renderer.non_finite() == 0);
    return renderer.mean_radiance();
  };
  const std::vector<Vec3f> cpu = render(Backend::cpu);
  REQUIRE(pixel_statistics(cpu).mean > 0.1); // lit: a black image would agree with anything
  CHECK(relative_difference(cpu, render(Backend::gpu)) < 0.02);
}
