// Chapter 08: each memory path as a tracer. See memory_tracers.h.
#include "memory_tracers.h"

#include <memory>
#include <optional>

#include "memory_trace.h"
#include "model_render.h"
#include "packed_bvh.h"

namespace rt::ch08 {
namespace {

using ch07::Tracer;
using ch07::TracerScene;

// One scene's trees in every layout, host and (GPU) device, shared by its tracers.
struct SceneTrees {
  ch07::Bvh bvh;
  PackedBvh packed;
  std::optional<DeviceTrees> device;
};

std::shared_ptr<SceneTrees> scene_trees(const TracerScene& scene, bool textures) {
  auto trees = std::make_shared<SceneTrees>(SceneTrees{scene.bvh, pack_bvh(scene.bvh), {}});
  if (scene.backend == Backend::gpu) {
    ch05::check_device_memory(device_tree_bytes(scene.bvh), scene.name);
    trees->device.emplace(trees->bvh, trees->packed, textures);
  }
  return trees;
}

double bytes_per_triangle(const SceneTrees& trees, MemoryPath path) {
  const double triangles = double(std::max<std::size_t>(1, trees.bvh.triangles.size()));
  if (path == MemoryPath::global || path == MemoryPath::ldg)
    return trees.bvh.stats.bytes_per_triangle;
  return double((trees.packed.nodes.size() + trees.packed.triangles.size()) * sizeof(float4)) /
         triangles;
}

Tracer path_tracer(MemoryPath path, const std::shared_ptr<SceneTrees>& trees, Backend backend) {
  Tracer tracer;
  tracer.name = to_string(path);
  tracer.bytes_per_triangle = bytes_per_triangle(*trees, path);
  if (runs_on(path, Backend::cpu))
    tracer.trace_cpu = [path, trees](ch07::Query query, std::span<const RayF> rays,
                                     std::span<MeshHit> hits) {
      trace_rays_path_cpu(path, query, trees->bvh, trees->packed, rays, hits);
    };
  if (backend == Backend::gpu) {
    tracer.trace_gpu = [path, trees](ch07::Query query, const RayF* d_rays, int count,
                                     MeshHit* d_hits) {
      trace_rays_path_gpu(path, query, *trees->device, d_rays, count, d_hits);
    };
    tracer.registers = [path](ch07::Query query) { return path_kernel_registers(path, query); };
  }
  return tracer;
}

// The kept path with the primary rays made in the kernel: no ray buffer read.
Tracer camera_tracer(ConstantsIn where, const std::shared_ptr<SceneTrees>& trees,
                     const TracerScene& scene) {
  const auto camera_trace =
      std::make_shared<const CameraTrace>(*trees->device, scene.camera, where);
  Tracer tracer;
  tracer.name =
      std::string(to_string(k_kept_path)) + ", camera and tree in " + to_string(where);
  tracer.bytes_per_triangle = bytes_per_triangle(*trees, k_kept_path);
  tracer.camera_rays_only = true;
  tracer.trace_gpu = [camera_trace, trees](ch07::Query, const RayF*, int, MeshHit* d_hits) {
    camera_trace->launch(d_hits);
  };
  tracer.registers = [camera_trace](ch07::Query) { return camera_trace->registers(); };
  return tracer;
}

} // namespace

ch07::TracerMaker memory_path_tracers(std::vector<MemoryPath> paths, bool camera_in_kernel) {
  return [paths, camera_in_kernel](const TracerScene& scene) {
    bool textures = false;
    for (const MemoryPath p : paths)
      textures = textures || (p == MemoryPath::texture && scene.backend == Backend::gpu);
    const std::shared_ptr<SceneTrees> trees = scene_trees(scene, textures);
    std::vector<Tracer> tracers;
    for (const MemoryPath path : paths)
      if (runs_on(path, scene.backend))
        tracers.push_back(path_tracer(path, trees, scene.backend));
    if (camera_in_kernel && scene.backend == Backend::gpu)
      for (const ConstantsIn where : {ConstantsIn::parameters, ConstantsIn::constant_memory})
        tracers.push_back(camera_tracer(where, trees, scene));
    return tracers;
  };
}

ch07::TracerMaker kept_tracer() { return memory_path_tracers({k_kept_path}, false); }

} // namespace rt::ch08
