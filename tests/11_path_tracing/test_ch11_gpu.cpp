// Chapter 11 tests on the GPU: the same sample numbers give the CPU's sums bit for bit, for
// the megakernel, the persistent threads and the wavefront alike, and for a moved scene whose
// tree is built on the GPU; the persistent threads add every pixel's samples exactly once.
//
// Why bit for bit and not "nearly": every step of a path is the same float operation on both
// backends, rounded the same way.
//  - The random numbers are integer hashes (path_random.h).
//  - The bounce is chapter 07's cosine-weighted direction, whose sine and cosine are plain
//    multiplies and adds (sin_cos_turns), not the GPU's sincospif and the C library's sin.
//  - The kernels are compiled with -fmad=false (CMakeLists.txt) and the CPU's code with
//    -ffp-contract=off, so no a * b + c is fused on either side, and the explicit FMAs of
//    chapters 04 and 09 are FMAs on both. Division and square root are correctly rounded on
//    both (nvcc's defaults, no fast math); no other maths function is on a path's way.
//  - The tree is the same: built on the host and uploaded, or built by chapter 10's LBVH on
//    either backend, which makes the same tree bit for bit; chapter 09's traversal finds the
//    same hits in it on both.
//  - A pixel's sum gets its samples one at a time, in sample order, in add_sample, on both.
// So a difference of one pixel is a bug, and the tests ask for none.
#include <cmath>
#include <utility>

#include "rt_catch.h"

#include "animation.h"
#include "gpu_guard.h"
#include "path_cases.h"

using namespace rt;
using namespace rt::ch11;
using namespace rt::ch11::testing;

namespace {

// What a failure reports: how many pixels differ, and by how much on average, relative to the
// mean sum.
void describe_difference(const std::vector<float4>& a, const std::vector<float4>& b) {
  long long differing = 0;
  double difference = 0.0, mean = 0.0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    differing += a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z || a[i].w != b[i].w;
    difference +=
        std::abs(a[i].x - b[i].x) + std::abs(a[i].y - b[i].y) + std::abs(a[i].z - b[i].z);
    mean += a[i].x + a[i].y + a[i].z;
  }
  UNSCOPED_INFO(differing << " of " << a.size() << " pixels differ, mean absolute difference "
                          << difference / mean << " of the mean");
}

PathScene room_with_sky_and_sun() {
  PathScene room = load_path_scene(k_room);
  room.environment.sky = {0.2f, 0.3f, 0.4f};
  room.environment.sun_direction = normalize(Vec3f{0.3f, 1.0f, 0.5f});
  room.environment.sun_irradiance = {1.0f, 1.0f, 1.0f};
  return room;
}

struct Sums {
  std::vector<float4> sums;
  unsigned long long non_finite;
};

Sums render(const PathScene& scene, Backend backend, Extent extent, int samples,
            const RenderSettings& settings) {
  PathRenderer renderer(scene, backend);
  renderer.restart(cornell_camera(), extent);
  renderer.add_samples(settings, samples);
  return {renderer.sums(), renderer.non_finite()};
}

} // namespace

TEST_CASE("GPU and CPU give the same sums, bit for bit, in every variant and kernel",
          "[ch11][gpu]") {
  RT_REQUIRE_GPU();
  const PathScene room = load_path_scene(k_room); // lit by its own light alone
  const PathScene lit = room_with_sky_and_sun();  // every feature on
  const Extent extent{64, 48};
  for (const PathScene* scene : {&room, &lit}) {
    for (const KernelKind kernel : {KernelKind::specialised, KernelKind::all_features}) {
      const RenderSettings cpu_settings{PathVariant::megakernel, kernel, Strategy::mis};
      const Sums cpu = render(*scene, Backend::cpu, extent, 8, cpu_settings);
      for (const PathVariant variant :
           {PathVariant::megakernel, PathVariant::persistent, PathVariant::wavefront}) {
        CAPTURE(scene == &lit, to_string(variant), kernel == KernelKind::specialised);
        const Sums gpu =
            render(*scene, Backend::gpu, extent, 8, {variant, kernel, Strategy::mis});
        CHECK(gpu.non_finite == 0);
        describe_difference(cpu.sums, gpu.sums);
        CHECK(same_sums(cpu.sums, gpu.sums));
      }
    }
  }
  // Each strategy on its own takes other branches of shade_vertex.
  for (const Strategy strategy : {Strategy::bsdf, Strategy::light}) {
    CAPTURE(to_string(strategy));
    const RenderSettings settings{PathVariant::megakernel, KernelKind::specialised, strategy};
    const Sums cpu = render(lit, Backend::cpu, extent, 8, settings);
    const Sums gpu = render(lit, Backend::gpu, extent, 8, settings);
    describe_difference(cpu.sums, gpu.sums);
    CHECK(same_sums(cpu.sums, gpu.sums));
  }
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

TEST_CASE("GPU: the wavefront's stragglers, run beside the next sample, change no sum",
          "[ch11][gpu]") {
  RT_REQUIRE_GPU();
  const PathScene lit = room_with_sky_and_sun();
  // 19 200 pixels: the stragglers' bar is 2 400 paths, which every sample's paths reach.
  const Extent extent{160, 120};
  const int samples = 6;
  PathRenderer renderer(lit, Backend::gpu);
  renderer.restart(cornell_camera(), extent);
  const WavefrontPass pass = renderer.add_samples(
      {PathVariant::wavefront, KernelKind::specialised, Strategy::mis}, samples);
  CHECK(pass.tails_beside == samples - 1);
  const std::vector<float4> wavefront = renderer.sums();
  for (const float4& s : wavefront) REQUIRE(s.w == float(samples)); // each sample once
  const Sums mega = render(lit, Backend::gpu, extent, samples,
                           {PathVariant::megakernel, KernelKind::specialised, Strategy::mis});
  describe_difference(mega.sums, wavefront);
  CHECK(same_sums(mega.sums, wavefront));
  // One sample per call has no next sample: the stragglers run as before.
  renderer.restart(cornell_camera(), extent);
  CHECK(
      renderer.add_samples({PathVariant::wavefront, KernelKind::specialised, Strategy::mis}, 1)
          .tails_beside == 0);
}

TEST_CASE("GPU: a moved scene, its tree built on the GPU, gives the CPU's sums bit for bit",
          "[ch11][gpu]") {
  RT_REQUIRE_GPU();
  const PathScene start = lit_moving_scene(0.0, 24);
  const std::vector<Vec3f> later = lit_moving_scene(0.9, 24).mesh.vertices;
  const Extent extent{64, 48};
  const auto render_moved = [&](Backend backend) {
    PathRenderer renderer(start, backend, TreeBuild::lbvh);
    renderer.restart(ch10::moving_scene_camera(), extent);
    renderer.move_vertices(later);
    renderer.add_samples({PathVariant::persistent, KernelKind::specialised, Strategy::mis}, 8);
    CHECK(renderer.non_finite() == 0);
    return std::pair{renderer.sums(), renderer.mean_radiance()};
  };
  const auto [cpu, cpu_mean] = render_moved(Backend::cpu);
  REQUIRE(pixel_statistics(cpu_mean).mean > 0.1); // lit: black images would agree with anything
  const std::vector<float4> gpu = render_moved(Backend::gpu).first;
  describe_difference(cpu, gpu);
  CHECK(same_sums(cpu, gpu));
}

TEST_CASE("GPU and CPU give the same sums, bit for bit, with every sampler in every variant",
          "[ch11][gpu]") {
  RT_REQUIRE_GPU();
  // The samplers are integer arithmetic on both backends (the GPU's __brev and the CPU's
  // shifts reverse the same bits), so their numbers, and the paths, are the same.
  const PathScene lit = room_with_sky_and_sun();
  // A size that is no power of two (zsobol's square is 64 x 64) and a count that is neither a
  // square nor a power of two (stratified's grid of 3 x 3 and 3 more, zsobol's nets of 16).
  const Extent extent{61, 43};
  const int samples = 12;
  for (const SamplerKind sampler : k_samplers) {
    RenderSettings settings{PathVariant::megakernel, KernelKind::specialised, Strategy::mis};
    settings.sampler = sampler;
    settings.sampler_samples = samples;
    const Sums cpu = render(lit, Backend::cpu, extent, samples, settings);
    for (const PathVariant variant :
         {PathVariant::megakernel, PathVariant::persistent, PathVariant::wavefront}) {
      CAPTURE(to_string(sampler), to_string(variant));
      settings.variant = variant;
      const Sums gpu = render(lit, Backend::gpu, extent, samples, settings);
      CHECK(gpu.non_finite == 0);
      describe_difference(cpu.sums, gpu.sums);
      CHECK(same_sums(cpu.sums, gpu.sums));
    }
  }
}
