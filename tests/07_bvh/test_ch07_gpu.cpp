// Chapter 07 tests on the GPU: the traversal kernel gives the CPU's hits bit for bit (both
// queries, both triangle tests, random and hostile rays), brute force on the GPU agrees with
// the CPU's, and the shaded frame traced through the tree is chapter 06's frame.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "rt_catch.h"

#include "bvh_cases.h"

#include "bvh_build.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "gpu_guard.h"
#include "obj_loader.h"
#include "rt/device_buffer.h"
#include "shaded_render.h"
#include "shaded_scene.h"

using namespace rt;
using namespace rt::ch07;
using namespace rt::testing;
using ch04::TriangleVariant;

namespace {

// Random rays into sphere_over_box(), and a few at the edge: NaN, infinity, no direction, along
// the box's top face, from far away.
std::vector<RayF> rays_for_tests(int count) {
  std::mt19937 rng(5);
  std::vector<RayF> rays = rays_towards_origin(rng, count, Intervals::whole);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  rays.push_back({{nan, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}});
  rays.push_back({{0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, inf}});
  rays.push_back({{0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f}});
  rays.push_back({{0.0f, -1.5f, 5.0f}, {0.0f, -0.0f, -1.0f}}); // along the box's top face
  rays.push_back({{1e6f, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f}});   // from far away
  return rays;
}

// The same triangle for every ray, and the same t: bit for bit with the watertight test, whose
// arithmetic fuses explicitly.
bool same_hits(const std::vector<ch04::MeshHit>& a, const std::vector<ch04::MeshHit>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].triangle != b[i].triangle || (a[i].triangle >= 0 && a[i].t != b[i].t))
      return false;
  return true;
}

// Moller-Trumbore's dot products are contracted into FMAs by nvcc on the GPU only, so its t
// differs from the CPU's in the last bits (relative errors near 1e-6 for short rays), and a ray
// within rounding of a shared edge may keep the other triangle (the test is not watertight).
// Rays that differ by more than that: another triangle, or t off by more than 1e-4 relative.
long long differing_beyond_rounding(const std::vector<ch04::MeshHit>& a,
                                    const std::vector<ch04::MeshHit>& b) {
  long long differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    differing += a[i].triangle != b[i].triangle ||
                 (a[i].triangle >= 0 && !(std::abs(a[i].t - b[i].t) <= 1e-4f * b[i].t));
  return differing;
}

} // namespace

TEST_CASE("GPU traversal gives the CPU's hits bit for bit", "[ch07][gpu]") {
  RT_REQUIRE_GPU();
  const ch04::Mesh mesh = sphere_over_box();
  const std::vector<RayF> rays = rays_for_tests(20000);
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    BuildOptions options;
    options.method = method;
    const Bvh bvh = build_bvh(mesh, options);
    for (const TriangleVariant variant :
         {TriangleVariant::moller_trumbore, TriangleVariant::watertight}) {
      for (const Query query : {Query::closest, Query::any}) {
        CAPTURE(to_string(method), ch04::to_string(variant), to_string(query));
        const auto gpu = trace_rays(Backend::gpu, query, variant, bvh, rays);
        const auto cpu = trace_rays(Backend::cpu, query, variant, bvh, rays);
        if (variant == TriangleVariant::watertight) {
          CHECK(same_hits(gpu, cpu));
        } else {
          const long long differing = differing_beyond_rounding(gpu, cpu);
          INFO(differing << " of " << rays.size() << " rays differ beyond rounding");
          CHECK(differing * 1000 <= static_cast<long long>(rays.size()));
        }
        if (query == Query::closest) {
          const std::vector<ch04::MeshHit> brute = ch04::closest_hits_cpu(variant, mesh, rays);
          const HitAgreement a = compare_hits(gpu, brute);
          CHECK(a.hits > 5000);
          if (variant == TriangleVariant::watertight)
            CHECK(a.mismatches == 0);
          else
            CHECK(differing_beyond_rounding(gpu, brute) * 1000 <=
                  static_cast<long long>(rays.size()));
        }
      }
    }
  }
}

TEST_CASE("GPU and CPU trace the 100k-triangle model's camera rays alike", "[ch07][gpu]") {
  RT_REQUIRE_GPU();
  const ch04::Mesh mesh = ch05::load_obj(RT_ASSETS_DIR "/torus_knot_100k.obj.gz").geometry;
  const Bvh bvh = build_bvh(mesh, {});
  const Extent extent{320, 180};
  const ch03::Camera<float> camera = ch03::make_camera<float>(
      ch06::frame_bounds_down_z(ch06::bounds_of(mesh), 40.0, extent), extent);
  std::vector<RayF> rays;
  for (int y = 0; y < extent.height; ++y)
    for (int x = 0; x < extent.width; ++x) rays.push_back(camera.ray_through_pixel(x, y));
  for (const TriangleVariant variant :
       {TriangleVariant::moller_trumbore, TriangleVariant::watertight}) {
    CAPTURE(ch04::to_string(variant));
    const auto gpu = trace_rays(Backend::gpu, Query::closest, variant, bvh, rays);
    const auto cpu = trace_rays(Backend::cpu, Query::closest, variant, bvh, rays);
    if (variant == TriangleVariant::watertight)
      CHECK(same_hits(gpu, cpu));
    else
      CHECK(differing_beyond_rounding(gpu, cpu) * 1000 <= static_cast<long long>(rays.size()));
    const HitAgreement a = compare_hits(gpu, ch04::closest_hits_cpu(variant, mesh, rays));
    CHECK(a.hits > 5000);
    if (variant == TriangleVariant::watertight) CHECK(a.mismatches == 0);
  }
}

TEST_CASE("GPU brute force agrees with the CPU's", "[ch07][gpu]") {
  RT_REQUIRE_GPU();
  const ch04::Mesh mesh = sphere_over_box();
  const std::vector<RayF> rays = rays_for_tests(3000);
  const DeviceBuffer<Vec3f> d_vertices{std::span<const Vec3f>(mesh.vertices)};
  const DeviceBuffer<ch04::IndexedTriangle> d_triangles{
      std::span<const ch04::IndexedTriangle>(mesh.triangles)};
  const DeviceBuffer<RayF> d_rays{std::span<const RayF>(rays)};
  DeviceBuffer<ch04::MeshHit> d_hits(rays.size());
  brute_force_gpu(TriangleVariant::watertight,
                  {d_vertices.data(), d_triangles.data(), int(mesh.triangles.size())},
                  d_rays.data(), int(rays.size()), d_hits.data());
  CHECK(same_hits(d_hits.to_host(),
                  ch04::closest_hits_cpu(TriangleVariant::watertight, mesh, rays)));
}

TEST_CASE("GPU shaded frame through the tree is chapter 06's frame", "[ch07][gpu]") {
  RT_REQUIRE_GPU();
  const auto [scene, bvh, extent, camera] = shaded_tree_case(3, {160, 90});
  for (const bool smooth : {false, true}) {
    CAPTURE(smooth);
    const unsigned features = ch06::features_used(scene, smooth, true);
    const ch06::DeviceShadedScene d_scene(scene, features);
    const DeviceBvh d_bvh(bvh);
    DeviceBuffer<Rgba8> d_tree(extent.pixel_count()), d_brute(extent.pixel_count());
    render_bvh_shaded(Backend::gpu, features, with_bvh(d_scene.view(), d_bvh.view()), camera,
                      extent, d_tree.data());
    ch06::render_shaded(Backend::gpu, ch06::KernelKind::specialised, features, d_scene.view(),
                        camera, extent, d_brute.data());
    std::vector<Rgba8> cpu(extent.pixel_count());
    render_bvh_shaded(Backend::cpu, features,
                      with_bvh(ch06::host_view(scene, features), bvh.view()), camera, extent,
                      cpu.data());
    const std::vector<Rgba8> tree = d_tree.to_host();
    CHECK(count_differing_pixels(tree, d_brute.to_host()) == 0);
    CHECK(count_differing_pixels(tree, cpu) == 0);
  }
}
