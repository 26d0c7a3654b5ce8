// Chapter 09 tests on the GPU: every wide tree's kernel gives the CPU traversal's hits bit for
// bit (the same RT_HD code, and dequantise rounds the same on both), for closest and any hits,
// and so do the traversal variants of wide4 packed (shared stack, persistent threads,
// sorted rays, tiles); so do the trees collapsed from spatial-split (sbvh) binary trees; the
// shaded frame through the compressed tree is the CPU's.
#include <cstring>
#include <vector>

#include "rt_catch.h"

#include "07_bvh/sbvh_cases.h"
#include "gpu_guard.h"
#include "rt/device_buffer.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "wide_cases.h"
#include "wide_render.h"
#include "wide_trace.h"

using namespace rt;
using namespace rt::ch09;
using namespace rt::ch09::testing;

namespace {

template <class Node, class Triangles>
int gpu_cpu_differences(const WideTree<Node, Triangles>& tree, const std::vector<RayF>& rays,
                        Query query) {
  std::vector<MeshHit> cpu(rays.size());
  trace_wide_cpu(query, tree.view(), rays, cpu);
  const DeviceWideTree<Node, Triangles> d_tree(tree);
  const DeviceBuffer<RayF> d_rays{std::span<const RayF>(rays)};
  DeviceBuffer<MeshHit> d_hits(rays.size());
  trace_wide_gpu(query, d_tree.view(), d_rays.data(), static_cast<int>(rays.size()),
                 d_hits.data());
  const std::vector<MeshHit> gpu = d_hits.to_host();
  int differ = 0;
  for (std::size_t i = 0; i < rays.size(); ++i)
    differ += std::memcmp(&cpu[i], &gpu[i], sizeof(MeshHit)) != 0;
  return differ;
}

// The hits of one GPU path of wide4 packed against the CPU traversal's, bit for bit; the hit
// buffer is poisoned first, so a ray the path skipped cannot pass.
template <class Trace>
int variant_differences(const Wide4PackedBvh& tree, const std::vector<RayF>& rays, Query query,
                        Trace trace) {
  std::vector<MeshHit> cpu(rays.size());
  trace_wide_cpu(query, tree.view(), rays, cpu);
  const DeviceWideTree<WideNode<4>, PackedTriangles> d_tree(tree);
  const DeviceBuffer<RayF> d_rays{std::span<const RayF>(rays)};
  DeviceBuffer<MeshHit> d_hits(rays.size());
  d_hits.fill_bytes(0xff);
  trace(query, d_tree.view(), d_rays.data(), static_cast<int>(rays.size()), d_hits.data());
  const std::vector<MeshHit> gpu = d_hits.to_host();
  int differ = 0;
  for (std::size_t i = 0; i < rays.size(); ++i)
    differ += std::memcmp(&cpu[i], &gpu[i], sizeof(MeshHit)) != 0;
  return differ;
}

} // namespace

TEST_CASE("gpu: the traversal variants give the CPU's hits bit for bit", "[ch09][gpu]") {
  RT_REQUIRE_GPU();
  using View = Wide4PackedBvh::View;
  for (const float offset : {0.0f, 1e5f}) {
    const Vec3f centre{offset, offset, -offset};
    const Mesh scene = mixed_scene(3000, 43, centre);
    std::vector<RayF> rays = rays_for(scene, 20000, 44, centre);
    rays.resize((rays.size() / 32 - 1) * 32 + 7); // the last warp not full
    const Wide4PackedBvh tree =
        pack_wide<4, PackedTriangles>(build_wide_layout(scene, 4, Collapse::sah));
    ch07::Aabb bounds;
    for (const Vec3f& v : scene.vertices) bounds.grow(v);
    PersistentWideTracer<View> persistent;
    SortedWideTracer<View> sorted(make_ray_sort_frame(bounds));
    const std::vector<RayF> few(rays.begin(), rays.begin() + 5); // fewer than a warp
    for (const Query query : {Query::closest, Query::any}) {
      CAPTURE(offset, ch07::to_string(query));
      CHECK(variant_differences(tree, rays, query, trace_wide_gpu_shared_stack<View>) == 0);
      const auto trace_persistent = [&](Query q, const View& v, const RayF* r, int n,
                                        MeshHit* h) { persistent.trace(q, v, r, n, h); };
      const auto trace_sorted = [&](Query q, const View& v, const RayF* r, int n, MeshHit* h) {
        sorted.trace(q, v, r, n, h);
      };
      // Twice each: the counter is reset, and the buffers reused, from one launch to the next.
      for (int launch = 0; launch < 2; ++launch) {
        CAPTURE(launch);
        CHECK(variant_differences(tree, rays, query, trace_persistent) == 0);
        CHECK(variant_differences(tree, rays, query, trace_sorted) == 0);
      }
      CHECK(variant_differences(tree, few, query, trace_persistent) == 0);
      CHECK(variant_differences(tree, few, query, trace_sorted) == 0);
      CHECK(variant_differences(tree, few, query, trace_wide_gpu_shared_stack<View>) == 0);
      // In tiles: the rays read as images whose tiles hang over both edges (one of them one
      // pixel wide), and as a list (the count not an image's), plain and persistent.
      for (const auto& [width, height] : {std::pair{157, 99}, std::pair{1, 5000}}) {
        CAPTURE(width, height);
        const std::vector<RayF> image(rays.begin(), rays.begin() + width * height);
        for (const int count : {width * height, width * height - 1}) {
          const std::vector<RayF> batch(image.begin(), image.begin() + count);
          const RayOrder order = RayOrder::for_image(count, width, height);
          CHECK(order.tiled() == (count == width * height));
          const auto trace_tiles = [&](Query q, const View& v, const RayF* r, int n,
                                       MeshHit* h) { trace_wide_gpu(q, v, r, n, h, order); };
          const auto trace_persistent_tiles = [&](Query q, const View& v, const RayF* r, int n,
                                                  MeshHit* h) {
            persistent.trace(q, v, r, n, h, order);
          };
          CHECK(variant_differences(tree, batch, query, trace_tiles) == 0);
          CHECK(variant_differences(tree, batch, query, trace_persistent_tiles) == 0);
        }
      }
    }
  }
  for (const Query query : {Query::closest, Query::any}) {
    CHECK(shared_stack_kernel_registers<View>(query) > 0);
    CHECK(PersistentWideTracer<View>::registers(query) > 0);
    CHECK(SortedWideTracer<View>::registers(query) > 0);
  }
  CHECK(SortedWideTracer<View>::key_kernel_registers() > 0);
}

TEST_CASE("gpu: every wide tree gives the CPU's hits bit for bit", "[ch09][gpu]") {
  RT_REQUIRE_GPU();
  for (const float offset : {0.0f, 1e5f}) {
    const Vec3f centre{offset, offset, -offset};
    const Mesh scene = mixed_scene(3000, 41, centre);
    const std::vector<RayF> rays = rays_for(scene, 20000, 42, centre);
    const WideTrees trees = all_wide_trees(scene);
    for (const Query query : {Query::closest, Query::any}) {
      CAPTURE(offset, ch07::to_string(query));
      CHECK(gpu_cpu_differences(trees.wide4_sah, rays, query) == 0);
      CHECK(gpu_cpu_differences(trees.wide4_greedy, rays, query) == 0);
      CHECK(gpu_cpu_differences(trees.wide8_sah, rays, query) == 0);
      CHECK(gpu_cpu_differences(trees.compressed_sah, rays, query) == 0);
      CHECK(gpu_cpu_differences(trees.compressed_greedy, rays, query) == 0);
      CHECK(gpu_cpu_differences(trees.wide4_packed, rays, query) == 0);
    }
  }
  CHECK(wide_kernel_registers<CompressedBvh::View>(Query::closest) > 0);
}

TEST_CASE("gpu: wide trees from sbvh trees give the CPU's hits bit for bit", "[ch09][gpu]") {
  RT_REQUIRE_GPU();
  using View = Wide4PackedBvh::View;
  ch07::BuildOptions options;
  options.method = ch07::SplitMethod::sbvh;
  options.split_budget = 1.0;
  for (const float offset : {0.0f, 1e5f}) {
    const Vec3f centre{offset, offset, -offset};
    Mesh slivers = rt::testing::long_slivers(3000, 45);
    for (Vec3f& v : slivers.vertices) v = v + centre;
    for (const Mesh& scene : {mixed_scene(3000, 46, centre), slivers}) {
      const std::vector<RayF> rays = rays_for(scene, 20000, 47, centre);
      const WideLayout four = build_wide_layout(scene, 4, Collapse::sah, options);
      const WideLayout eight = build_wide_layout(scene, 8, Collapse::sah, options);
      const Wide4PackedBvh packed = pack_wide<4, PackedTriangles>(four);
      REQUIRE(check_wide_tree(packed, scene, options).empty());
      CHECK(four.stats.references > static_cast<long long>(scene.triangles.size()));
      for (const Query query : {Query::closest, Query::any}) {
        CAPTURE(offset, scene.triangles.size(), ch07::to_string(query));
        CHECK(gpu_cpu_differences(packed, rays, query) == 0);
        CHECK(variant_differences(packed, rays, query, trace_wide_gpu_shared_stack<View>) == 0);
        CHECK(gpu_cpu_differences(pack_wide<8>(eight), rays, query) == 0);
        CHECK(gpu_cpu_differences(compress(eight), rays, query) == 0);
      }
    }
  }
}

TEST_CASE("gpu: the shaded frame through the compressed tree is the CPU's", "[ch09][gpu]") {
  RT_REQUIRE_GPU();
  const ShadedView view;
  const auto& [scene, tree, extent, camera] = view;
  const unsigned features = ch06::features_used(scene, true, true);
  std::vector<Rgba8> cpu(extent.pixel_count());
  render_wide_shaded(Backend::cpu, features,
                     with_wide(ch06::host_view(scene, features), tree.view()), camera, extent,
                     cpu.data());
  const ch06::DeviceShadedScene d_scene(scene, features);
  const DeviceWideTree<CompressedNode> d_tree(tree);
  DeviceBuffer<Rgba8> d_pixels(extent.pixel_count());
  render_wide_shaded(Backend::gpu, features, with_wide(d_scene.view(), d_tree.view()), camera,
                     extent, d_pixels.data());
  CHECK(count_differing_pixels(cpu, d_pixels.to_host()) == 0);
}

TEST_CASE("gpu: the wide heat map is the CPU's", "[ch09][gpu]") {
  RT_REQUIRE_GPU();
  const ShadedView view;
  const auto& [scene, tree, extent, camera] = view;
  std::vector<Rgba8> cpu(extent.pixel_count());
  render_wide_heat_map(Backend::cpu, tree.view(), camera, extent, cpu.data());
  const DeviceWideTree<CompressedNode> d_tree(tree);
  DeviceBuffer<Rgba8> d_pixels(extent.pixel_count());
  render_wide_heat_map(Backend::gpu, d_tree.view(), camera, extent, d_pixels.data());
  CHECK(count_differing_pixels(cpu, d_pixels.to_host()) == 0);
}
