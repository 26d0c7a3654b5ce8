// Chapter 13 tests on the GPU: the same scene of instances on CUDA threads and on CPU threads
// gives the same instances, the same top-level tree and the same hits (instance, triangle, t,
// u, v) bit for bit, closest and any, the same shaded image, and the same again after the
// trees have turned (move(): transforms and boxes made on the device in double).
#include <algorithm>
#include <span>
#include <vector>

#include "rt_catch.h"

#include "gpu_guard.h"
#include "instance_cases.h"
#include "instanced_paths.h"
#include "rt/backend_array.h"
#include "rt/device_buffer.h"
#include "two_level_scene.h"

using namespace rt;
using namespace rt::ch13;
using namespace rt::ch13::testing;

namespace {

// `count` values at a backend pointer, on the host.
template <class T> std::vector<T> to_host(Backend backend, const T* data, int count) {
  std::vector<T> out(static_cast<std::size_t>(count));
  if (count == 0) return out;
  if (backend == Backend::gpu)
    RT_CUDA_CHECK(cudaMemcpy(out.data(), data, out.size() * sizeof(T), cudaMemcpyDeviceToHost));
  else
    std::copy(data, data + count, out.begin());
  return out;
}

template <class T> long long count_differing(const std::vector<T>& a, const std::vector<T>& b) {
  long long differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differing += !same_bits(a[i], b[i]);
  return differing + static_cast<long long>(a.size() > b.size() ? a.size() - b.size()
                                                                : b.size() - a.size());
}

// The scene on one backend: its instances and top-level tree as that backend holds them.
struct Held {
  std::vector<Instance> instances;
  std::vector<ch07::BvhNode> top_nodes;
  std::vector<int> leaf_ids;
};
Held held(const TwoLevelScene& scene) {
  const TwoLevelView view = scene.view();
  const Backend b = scene.backend();
  return {to_host(b, view.instances, scene.instance_count()),
          to_host(b, view.top_nodes, view.top_node_count),
          to_host(b, view.top_leaf_ids, scene.instance_count())};
}

std::vector<InstanceHit> trace_on(const TwoLevelScene& scene, Query query,
                                  const std::vector<RayF>& rays) {
  const BackendArray<RayF> d_rays(scene.backend(), std::span<const RayF>(rays));
  BackendArray<InstanceHit> d_hits(scene.backend(), rays.size());
  trace_rays(scene, query, d_rays.data(), static_cast<int>(rays.size()), d_hits.data());
  return d_hits.to_host();
}

std::vector<Rgba8> shade_on(const TwoLevelScene& scene, const ch03::Camera<float>& camera,
                            Extent extent) {
  BackendArray<Rgba8> d_pixels(scene.backend(), static_cast<std::size_t>(extent.pixel_count()));
  render_shaded(scene, camera, extent, d_pixels.data());
  return d_pixels.to_host();
}

// Both backends' scenes, instances, trees, hits and images compared; `when` names the frame.
void check_same_on_both(const TwoLevelScene& gpu, const TwoLevelScene& cpu,
                        const std::vector<RayF>& rays, const ch03::Camera<float>& camera,
                        Extent extent, const char* when) {
  CAPTURE(when);
  const Held g = held(gpu), c = held(cpu);
  CHECK(count_differing(g.instances, c.instances) == 0);
  CHECK(count_differing(g.top_nodes, c.top_nodes) == 0);
  CHECK(g.leaf_ids == c.leaf_ids);
  for (const Query query : {Query::closest, Query::any}) {
    CAPTURE(query == Query::closest ? "closest" : "any");
    const std::vector<InstanceHit> on_gpu = trace_on(gpu, query, rays);
    const std::vector<InstanceHit> on_cpu = trace_on(cpu, query, rays);
    long long hits = 0;
    for (const InstanceHit& h : on_cpu) hits += h.instance >= 0;
    CAPTURE(hits);
    CHECK(hits > static_cast<long long>(rays.size()) / 10); // the rays meet the forest
    CHECK(count_differing(on_gpu, on_cpu) == 0);
  }
  const std::vector<Rgba8> image_gpu = shade_on(gpu, camera, extent);
  const std::vector<Rgba8> image_cpu = shade_on(cpu, camera, extent);
  long long differing_pixels = 0;
  for (std::size_t i = 0; i < image_cpu.size(); ++i)
    differing_pixels += !(image_gpu[i] == image_cpu[i]);
  CHECK(differing_pixels == 0);
}

} // namespace

TEST_CASE("a forest of 50 instances: the GPU's hits and image are the CPU's, bit for bit",
          "[ch13][gpu]") {
  RT_REQUIRE_GPU();
  const Forest forest = icosphere_forest(50, 1320, 0.9);
  const BottomLevel bottom = build_bottom_level(forest.scene.meshes);
  TwoLevelScene gpu(Backend::gpu, forest.scene, bottom, forest.spins);
  TwoLevelScene cpu(Backend::cpu, forest.scene, bottom, forest.spins);
  REQUIRE(gpu.instance_count() == 51);
  // Rays from around the forest into it, and rays from above down onto it (the ground).
  std::vector<RayF> rays = rays_into_box(scene_box(forest.scene), 0.4, 20000, 1321);
  const Extent extent{96, 64};
  const ch03::Camera<float> camera = ch03::make_camera<float>(*forest.scene.camera, extent);
  for (int y = 0; y < extent.height; y += 2)
    for (int x = 0; x < extent.width; x += 2) rays.push_back(camera.ray_through_pixel(x, y));
  check_same_on_both(gpu, cpu, rays, camera, extent, "as built");
  gpu.move(0.5);
  cpu.move(0.5);
  check_same_on_both(gpu, cpu, rays, camera, extent, "after move(0.5)");
  // The top level rebuilt over the same boxes is the same tree.
  gpu.build_top();
  cpu.build_top();
  check_same_on_both(gpu, cpu, rays, camera, extent, "after build_top()");
}

TEST_CASE("the wide top level: the GPU's hits and image are the CPU's, bit for bit",
          "[ch13][gpu][wide-top]") {
  // The top level collapsed to chapter 09's 4-wide node by chapter 10's parallel collapse, on
  // both backends, as built and after the trees have turned.
  // Both of its walks: chapter 09's nested, and both levels in one loop.
  RT_REQUIRE_GPU();
  const Forest forest = icosphere_forest(300, 1330, 0.7);
  const BottomLevel bottom = build_bottom_level(forest.scene.meshes);
  std::vector<RayF> rays = rays_into_box(scene_box(forest.scene), 0.4, 20000, 1331);
  const Extent extent{96, 64};
  const ch03::Camera<float> camera = ch03::make_camera<float>(*forest.scene.camera, extent);
  for (const TopLayout top : {TopLayout::nested, TopLayout::wide}) {
    TwoLevelScene gpu(Backend::gpu, forest.scene, bottom, forest.spins, top);
    TwoLevelScene cpu(Backend::cpu, forest.scene, bottom, forest.spins, top);
    const std::string name = top == TopLayout::wide ? "one loop" : "nested";
    check_same_on_both(gpu, cpu, rays, camera, extent, (name + ", as built").c_str());
    gpu.move(1.5);
    cpu.move(1.5);
    check_same_on_both(gpu, cpu, rays, camera, extent, (name + ", after move(1.5)").c_str());
  }
}

TEST_CASE("paths through two levels: the GPU's radiance is the CPU's, bit for bit",
          "[ch13][gpu][paths]") {
  // Chapter 11's stateless random numbers and unfused arithmetic: the same paths on both
  // backends, so the same mean radiance in every pixel, for both top levels.
  RT_REQUIRE_GPU();
  const Forest forest = icosphere_forest(60, 1360, 0.4);
  const BottomLevel bottom = build_bottom_level(forest.scene.meshes);
  const Extent extent{64, 48};
  const ch03::Camera<float> camera = ch03::make_camera<float>(*forest.scene.camera, extent);
  PathSettings settings;
  settings.samples = 8;
  for (const TopLayout top : {TopLayout::binary, TopLayout::nested, TopLayout::wide}) {
    TwoLevelScene gpu(Backend::gpu, forest.scene, bottom, forest.spins, top);
    TwoLevelScene cpu(Backend::cpu, forest.scene, bottom, forest.spins, top);
    BackendArray<Vec3f> on_gpu(Backend::gpu, static_cast<std::size_t>(extent.pixel_count()));
    std::vector<Vec3f> on_cpu(static_cast<std::size_t>(extent.pixel_count()));
    render_paths(gpu, camera, extent, settings, on_gpu.data(), nullptr);
    render_paths(cpu, camera, extent, settings, on_cpu.data(), nullptr);
    CAPTURE(int(top));
    CHECK(count_differing(on_gpu.to_host(), on_cpu) == 0);
  }
}

TEST_CASE("the GPU's moved instances are the host's placed_instance and world_box",
          "[ch13][gpu]") {
  // move() makes every transform from its spin in double on the device (sincos) and on the
  // host (std::sin, std::cos): both are rounded to float after, and must agree with what the
  // host makes for the same time.
  RT_REQUIRE_GPU();
  const Forest forest = icosphere_forest(50, 1322, -1.7);
  const BottomLevel bottom = build_bottom_level(forest.scene.meshes);
  TwoLevelScene gpu(Backend::gpu, forest.scene, bottom, forest.spins);
  for (const double seconds : {0.5, 3.25, -20.0}) {
    CAPTURE(seconds);
    gpu.move(seconds);
    const Held g = held(gpu);
    long long differing = 0;
    for (std::size_t k = 0; k < forest.spins.size(); ++k)
      differing +=
          !same_bits(g.instances[k],
                     placed_instance(spin_transform(forest.spins[k], seconds), 0, 0xffffffffu));
    CHECK(differing == 0);
    // Each leaf's box in its parent: the host's world_box of the same transform.
    long long boxes_differing = 0, leaves = 0;
    for (const ch07::BvhNode& node : g.top_nodes)
      for (int c = 0; c < 2; ++c) {
        if (!node.is_leaf(c)) continue;
        const int id = g.leaf_ids[node.first[c]];
        const AffineD to_world = id < int(forest.spins.size())
                                     ? spin_transform(forest.spins[id], seconds)
                                     : forest.scene.placements[id].to_world;
        const int mesh = forest.scene.placements[id].mesh;
        boxes_differing +=
            !same_bits(node.box[c], world_box(bottom.object_boxes[mesh], to_world));
        ++leaves;
      }
    CHECK(leaves == 51);
    CHECK(boxes_differing == 0);
  }
}
