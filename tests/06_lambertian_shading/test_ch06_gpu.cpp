// Chapter 06 tests on the GPU, built with nvcc's default flags: each specialised kernel gives
// the same image as the all-features kernel, GPU frames agree with the CPU's, only the arrays
// a kernel reads are uploaded, and no shadow acne appears at any scale.
#include <cstdio>
#include <vector>

#include "rt_catch.h"

#include "gpu_guard.h"
#include "rt/device_buffer.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "shading_cases.h"

using namespace rt;
using namespace rt::ch06;
using rt::testing::records_differing;
using rt::testing::render_cpu;
using rt::testing::ShadedFrame;

namespace {

ShadedFrame render(Backend backend, const ShadedScene& scene, KernelKind kind,
                   unsigned features, const CameraSpec& spec, Extent extent) {
  if (backend == Backend::cpu) return render_cpu(scene, kind, features, spec, extent);
  ShadedFrame frame{Image(extent.width, extent.height),
                    std::vector<ShadedPixelRecord>(extent.pixel_count())};
  const DeviceShadedScene d_scene(scene, uploaded_features(kind, features));
  DeviceBuffer<Rgba8> d_pixels(frame.image.pixels.size());
  DeviceBuffer<ShadedPixelRecord> d_records(frame.records.size());
  d_pixels.fill_bytes(0xff); // poisoned: a pixel the kernel skips shows
  render_shaded(backend, kind, features, d_scene.view(), ch03::make_camera<float>(spec, extent),
                extent, d_pixels.data(), d_records.data());
  d_pixels.download(frame.image.pixels);
  d_records.download(frame.records);
  return frame;
}

} // namespace

TEST_CASE("GPU specialised kernels give the all-features kernel's images", "[ch06][gpu]") {
  RT_REQUIRE_GPU();
  const ShadedScene scene = make_default_scene(2, 1.0, LightSettings{});
  const CameraSpec spec = default_camera(1.0);
  const Extent extent{160, 90};
  for (unsigned features = 0; features <= k_all_features; ++features) {
    CAPTURE(features, describe_features(features));
    const ShadedFrame specialised =
        render(Backend::gpu, scene, KernelKind::specialised, features, spec, extent);
    const ShadedFrame generic =
        render(Backend::gpu, scene, KernelKind::all_features, features, spec, extent);
    CHECK(count_differing_pixels(specialised.image.pixels, generic.image.pixels) == 0);
    CHECK(records_differing(specialised.records, generic.records) == 0);
    const int registers = kernel_registers(KernelKind::specialised, features);
    std::printf("GPU kernel for %-38s %3d registers (all-features kernel: %d)\n",
                describe_features(features).c_str(), registers,
                kernel_registers(KernelKind::all_features, features));
    CHECK(registers > 0);
  }
}

TEST_CASE("GPU frames agree with the CPU's and have no NaN", "[ch06][gpu]") {
  RT_REQUIRE_GPU();
  const ShadedScene scene = make_default_scene(2, 1.0, LightSettings{});
  const CameraSpec spec = default_camera(1.0);
  const Extent extent{320, 180};
  for (const bool smooth : {false, true}) {
    for (const bool shadows : {false, true}) {
      const unsigned features = features_used(scene, smooth, shadows);
      const ShadedFrame gpu =
          render(Backend::gpu, scene, KernelKind::specialised, features, spec, extent);
      const ShadedFrame cpu =
          render(Backend::cpu, scene, KernelKind::specialised, features, spec, extent);
      const ShadedFrameError against_cpu =
          compare_with_reference(gpu.image, gpu.records, cpu.image);
      CAPTURE(smooth, shadows, against_cpu.pixels_differing, against_cpu.rmse);
      // FMA contraction on the GPU rounds a few products differently: a grazing shadow ray or
      // an 8-bit value may go the other way, nothing more.
      CHECK(against_cpu.pixels_differing <= extent.pixel_count() / 200);
      CHECK(against_cpu.rmse < 1.0);
      CHECK(against_cpu.nan_pixels == 0);
      CHECK(records_differing(gpu.records, cpu.records) <= extent.pixel_count() / 200);
    }
  }
}

TEST_CASE("GPU uploads only what the kernel reads", "[ch06][gpu]") {
  RT_REQUIRE_GPU();
  const ShadedScene scene = make_default_scene(2, 1.0, LightSettings{});
  for (unsigned features = 0; features <= k_all_features; ++features) {
    CAPTURE(features);
    const DeviceShadedScene d_scene(scene, features);
    CHECK(d_scene.bytes_uploaded() == scene_bytes(scene, features));
    const SceneView view = d_scene.view();
    CHECK((view.normals == nullptr) == ((features & k_smooth_normals) == 0));
  }
  CHECK(scene_bytes(scene, 0) < scene_bytes(scene, k_all_features));
}

TEST_CASE("GPU: no shadow acne on a convex mesh at scales 1 to 1e6", "[ch06][gpu]") {
  RT_REQUIRE_GPU();
  const Extent extent{160, 90};
  for (const double scale : {1.0, 1e3, 1e6}) {
    const ShadedScene sphere = make_lone_sphere(3, scale, LightSettings{});
    const CameraSpec spec = frame_bounds_down_z(bounds_of(sphere.mesh), 40.0, extent);
    for (const bool smooth : {false, true}) {
      const unsigned features = features_used(sphere, smooth, true);
      const ShadedFrame frame =
          render(Backend::gpu, sphere, KernelKind::specialised, features, spec, extent);
      long long rays = 0, acne = 0, nan = 0;
      for (const ShadedPixelRecord& r : frame.records) {
        rays += r.shadow_rays;
        acne += r.shadowed_facing;
        nan += r.nan;
      }
      CAPTURE(scale, smooth, rays);
      CHECK(rays > 1000);
      CHECK(acne == 0);
      CHECK(nan == 0);
    }
  }
}
