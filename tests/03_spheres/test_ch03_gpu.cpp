// Chapter 03 tests on the GPU: camera rays bit for bit the CPU's, sphere hits the CPU's, and
// the stiff cases still right with nvcc's default FMA contraction.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "rt_catch.h"

#include "gpu_guard.h"
#include "render.h"
#include "rt/device_buffer.h"
#include "sphere_cases.h"
#include "spheres.h"

using namespace rt;
using namespace rt::ch03;
using rt::testing::distance_to_ray_line;
using rt::testing::far_sphere_case;
using rt::testing::ground_sphere_case;
using rt::testing::stable_silhouette_band;

namespace {

constexpr float k_epsilon = std::numeric_limits<float>::epsilon();
// How far GPU and CPU roots of the stable test may differ away from the silhouette: FMA
// contraction rounds the dot products differently. Measured on the CPU with contraction
// forced on (g++ -mfma -ffp-contract=fast): at most 6 ulps.
constexpr double k_stable_t_tolerance = 16 * k_epsilon;

// GPU and CPU hits of the same rays: identical hit or miss for rays farther than `band` from
// the silhouette (closer ones may flip where FMA contraction rounds differently), t within
// `t_tolerance` relative. Returns the number of rays that broke either rule.
long long count_disagreements(const std::vector<RayF>& rays, SphereF sphere,
                              const std::vector<SphereHitF>& gpu,
                              const std::vector<SphereHitF>& cpu, double band,
                              double t_tolerance) {
  long long disagreements = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (std::isnan(gpu[i].t)) ++disagreements;
    const double miss_distance = distance_to_ray_line(rays[i], sphere) - sphere.radius;
    if (std::abs(miss_distance) <= band) continue;
    if (gpu[i].hit != cpu[i].hit) {
      ++disagreements;
    } else if (gpu[i].hit &&
               !(std::abs(double(gpu[i].t) - cpu[i].t) <= t_tolerance * double(cpu[i].t))) {
      ++disagreements;
    }
  }
  return disagreements;
}

} // namespace

TEST_CASE("GPU camera rays are bit for bit the CPU's", "[ch03][gpu]") {
  RT_REQUIRE_GPU();
  const PinholeCamera<float> conference = make_pinhole_camera(
      Vec3f{-300, 400, 300}, Vec3f{1000, 100, -700}, Vec3f{0, 1, 0}, 60.0f, 1920, 1080);
  const PinholeCamera<float> sponza =
      make_pinhole_camera(Vec3f{-14, 3, 0}, Vec3f{10, 5, 0}, Vec3f{0, 1, 0}, 60.0f, 641, 359);
  for (const PinholeCamera<float>& camera : {conference, sponza}) {
    const std::vector<RayF> gpu = pinhole_rays_gpu(camera);
    const std::vector<RayF> cpu = pinhole_rays_cpu(camera);
    REQUIRE(gpu.size() == cpu.size());
    long long differing = 0;
    for (std::size_t i = 0; i < gpu.size(); ++i)
      differing += gpu[i].direction != cpu[i].direction || gpu[i].origin != cpu[i].origin;
    CAPTURE(camera.width, camera.height);
    CHECK(differing == 0);
  }
}

TEST_CASE("GPU sphere hits equal the CPU's for camera rays", "[ch03][gpu]") {
  RT_REQUIRE_GPU();
  const PinholeCamera<float> camera =
      make_pinhole_camera(Vec3f{0, 0, 5}, Vec3f{0.1f, 0, 0}, Vec3f{0, 1, 0}, 45.0f, 400, 300);
  const SphereF sphere{{0.25f, -0.1f, 0.0f}, 1.0f};
  const std::vector<RayF> rays = pinhole_rays_cpu(camera);
  for (const SphereVariant variant : {SphereVariant::textbook, SphereVariant::stable}) {
    CAPTURE(to_string(variant));
    const auto gpu = intersect_spheres_gpu(variant, rays, sphere);
    const auto cpu = intersect_spheres_cpu(variant, rays, sphere);
    REQUIRE(gpu.size() == rays.size());
    // Away from the silhouette the stable roots agree to a few ulps; the textbook roots
    // inherit the cancellation of b^2 - 4ac and agree only to about 1e-4.
    const double t_tolerance = variant == SphereVariant::stable ? k_stable_t_tolerance : 1e-4;
    CHECK(count_disagreements(rays, sphere, gpu, cpu, 1e-3, t_tolerance) == 0);
  }
}

TEST_CASE("GPU stable test: small sphere far away hit iff float64 says so", "[ch03][gpu]") {
  RT_REQUIRE_GPU();
  for (const float distance : {1e3f, 1e4f, 1e5f}) {
    const auto [sphere, rays] = far_sphere_case(distance, 100'000, 4321);
    const auto stable = intersect_spheres_gpu(SphereVariant::stable, rays, sphere);
    const auto textbook = intersect_spheres_gpu(SphereVariant::textbook, rays, sphere);
    long long stable_wrong = 0, textbook_wrong = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const double miss_distance = distance_to_ray_line(rays[i], sphere) - sphere.radius;
      if (std::abs(miss_distance) <= stable_silhouette_band(rays[i], sphere)) continue;
      stable_wrong += stable[i].hit != (miss_distance < 0);
      textbook_wrong += textbook[i].hit != (miss_distance < 0);
    }
    std::printf(
        "GPU far sphere at %g radii: false hits or misses: stable %lld, textbook %lld\n",
        double(distance), stable_wrong, textbook_wrong);
    CAPTURE(distance, stable_wrong, textbook_wrong);
    CHECK(stable_wrong == 0);
    CHECK(textbook_wrong > 0);
    const auto cpu = intersect_spheres_cpu(SphereVariant::stable, rays, sphere);
    const double band = stable_silhouette_band(rays.front(), sphere); // one eye, one band
    CHECK(count_disagreements(rays, sphere, stable, cpu, band, k_stable_t_tolerance) == 0);
  }
}

TEST_CASE("GPU stable test: huge sphere near root within 1e-6 of float64", "[ch03][gpu]") {
  RT_REQUIRE_GPU();
  for (const float radius : {1e4f, 1e5f, 1e6f}) {
    const auto [sphere, rays] = ground_sphere_case(radius, 100'000, 77);
    const auto gpu = intersect_spheres_gpu(SphereVariant::stable, rays, sphere);
    const SphereD sphere_d{sphere.centre.as<double>(), double(sphere.radius)};
    double worst = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const SphereHitD reference = intersect_sphere_stable(ray_as<double>(rays[i]), sphere_d);
      REQUIRE(gpu[i].hit);
      worst = std::max(worst, std::abs(gpu[i].t - reference.t) / reference.t);
    }
    CAPTURE(radius, worst);
    CHECK(worst <= 1e-6);
  }
}

TEST_CASE("GPU render of the default scene agrees with the CPU's and with float64",
          "[ch03][gpu]") {
  RT_REQUIRE_GPU();
  const Extent extent{640, 360};
  const CameraSpec spec;
  const SphereScene<float> scene = make_default_scene();
  const Camera<float> camera = make_camera<float>(spec, extent);
  const ReferenceFrame reference = render_reference(scene, spec, extent, 4);
  for (SphereVariant variant : {SphereVariant::textbook, SphereVariant::stable}) {
    Image gpu(extent.width, extent.height), cpu(extent.width, extent.height);
    std::vector<PixelRecord> gpu_records(gpu.pixels.size()), cpu_records(cpu.pixels.size());
    DeviceBuffer<Rgba8> d_pixels(gpu.pixels.size());
    DeviceBuffer<PixelRecord> d_records(gpu.pixels.size());
    render_spheres(Backend::gpu, scene, camera, extent, {variant, 4}, d_pixels.data(),
                   d_records.data());
    d_pixels.download(gpu.pixels);
    d_records.download(gpu_records);
    render_spheres(Backend::cpu, scene, camera, extent, {variant, 4}, cpu.pixels.data(),
                   cpu_records.data());
    long long other_sphere = 0;
    for (std::size_t i = 0; i < gpu_records.size(); ++i)
      other_sphere += gpu_records[i].sphere != cpu_records[i].sphere;
    const FrameError e = compare_with_reference(gpu, gpu_records, reference);
    CAPTURE(to_string(variant), other_sphere, e.pixels_differing, e.max_relative_t_error);
    // FMA contraction on the GPU rounds some products differently: a handful of silhouette
    // pixels may change sphere, and shading may round across an 8-bit step.
    CHECK(other_sphere <= 8);
    CHECK(static_cast<long long>(count_differing_pixels(gpu.pixels, cpu.pixels)) <=
          extent.pixel_count() / 100);
    CHECK(e.nan_pixels == 0);
    if (variant == SphereVariant::stable) {
      CHECK(e.false_hits == 0);
      CHECK(e.false_misses == 0);
      CHECK(e.max_relative_t_error < 1e-4);
    }
  }
}
