// Chapter 12 tests on the GPU. The path tracer's arithmetic is chapter 11's (its kernels
// compiled with -fmad=false), but chapter 12 adds the maths library: the ray cones' log2f and
// atanf, the Fresnel terms' powers and square roots of complex numbers, and the texture units'
// filtering with 8-bit weights. A function the GPU rounds one ulp apart from the C library can
// turn a path's Russian roulette or its lobe choice the other way; such a pixel differs by a
// whole sample. So the GPU is held to the CPU statistically (the image means agree within a
// stated tolerance, and almost every pixel is the same), and bit for bit between its own
// variants.
#include <cmath>
#include <utility>

#include "rt_catch.h"

#include "gpu_guard.h"
#include "material_cases.h"

using namespace rt;
using namespace rt::ch12;
using namespace rt::ch12::testing;

namespace {

// The share of pixels whose sums differ by more than `relative` of the larger.
double share_differing(const std::vector<float4>& a, const std::vector<float4>& b,
                       double relative) {
  long long differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double x = a[i].x + a[i].y + a[i].z, y = b[i].x + b[i].y + b[i].z;
    differing += std::abs(x - y) > relative * std::max({std::abs(x), std::abs(y), 1e-6});
  }
  return double(differing) / double(a.size());
}

} // namespace

TEST_CASE("GPU: the material room matches the CPU (means within 0.5%, most pixels alike)",
          "[ch12][gpu]") {
  // Through plain loads the textures are filtered as on the CPU, and 97% of the pixels are
  // alike; the texture units' 8-bit weights turn a few more paths (the H200: 3.3%).
  RT_REQUIRE_GPU();
  const MaterialScene room = load_material_scene(k_room_gltf);
  const Extent extent{64, 48};
  for (const bool objects : {false, true}) {
    CAPTURE(objects);
    const MaterialOptions options{.texture_objects = objects};
    const Render cpu = render(room, Backend::cpu, *room.camera, extent, 16, {}, options);
    const Render gpu = render(room, Backend::gpu, *room.camera, extent, 16, {}, options);
    CHECK(gpu.non_finite == 0);
    const MeanAndError c = pixel_statistics(cpu.mean), g = pixel_statistics(gpu.mean);
    CAPTURE(c.mean, g.mean, c.standard_error);
    CHECK(std::abs(c.mean - g.mean) < 0.005 * c.mean);
    const double share = share_differing(cpu.sums, gpu.sums, 1e-3);
    CAPTURE(share);
    CHECK(share < (objects ? 0.05 : 0.03));
  }
}

TEST_CASE("GPU: megakernel, persistent threads and wavefront give the same sums, bit for bit",
          "[ch12][gpu]") {
  RT_REQUIRE_GPU();
  const MaterialScene room = load_material_scene(k_room_gltf);
  for (const Extent extent : {Extent{61, 43}, Extent{8, 4}}) {
    const Render first = render(room, Backend::gpu, *room.camera, extent, 4);
    for (const PathVariant variant : {PathVariant::persistent, PathVariant::wavefront})
      for (const ch06::KernelKind kind :
           {ch06::KernelKind::specialised, ch06::KernelKind::all_features}) {
        CAPTURE(ch11::to_string(variant), int(kind), extent.width);
        const Render r = render(room, Backend::gpu, *room.camera, extent, 4,
                                {variant, kind, ch11::Strategy::mis});
        CHECK(ch11::testing::same_sums(r.sums, first.sums));
      }
  }
}

TEST_CASE("GPU: the furnace spheres are invisible there too", "[ch12][gpu]") {
  RT_REQUIRE_GPU();
  for (const auto& [name, roughness] :
       {std::pair{"glass", 0.0f}, std::pair{"rough-glass", 0.1f},
        std::pair{"white-metal", 0.5f}}) {
    CAPTURE(name, roughness);
    const MaterialScene scene = make_sphere_in_sky(named_material(name, roughness), 4, 1.0f);
    const Render r = render(scene, Backend::gpu, sphere_camera(), {64, 48}, 64);
    CHECK(r.non_finite == 0);
    CHECK(std::abs(pixel_statistics(r.mean).mean - 1.0) < 0.01);
  }
}
