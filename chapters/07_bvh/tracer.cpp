// Chapter 07: the chapter's own tracers: its tree, and brute force. See tracer.h.
#include "tracer.h"

#include <memory>

#include "rt/device_buffer.h"

namespace rt::ch07 {

const char* to_string(HitRule rule) {
  return rule == HitRule::identical ? "identical" : "ties allowed";
}

Tracer bvh_tracer(std::string name, Bvh bvh, const TracerScene& scene) {
  // The tracer's functions share the tree (and its GPU copy) and keep it alive.
  const auto tree = std::make_shared<const Bvh>(std::move(bvh));
  Tracer tracer;
  tracer.name = std::move(name);
  tracer.bytes_per_triangle = tree->stats.bytes_per_triangle;
  const TriangleVariant variant = scene.variant;
  tracer.trace_cpu = [tree, variant](Query query, std::span<const RayF> rays,
                                     std::span<MeshHit> hits) {
    trace_rays_cpu(query, variant, tree->view(), rays, hits);
  };
  tracer.work = [tree, variant](Query query, std::span<const RayF> rays) {
    return measure_work(query, variant, tree->view(), rays);
  };
  if (scene.backend == Backend::gpu) {
    const auto d_tree = std::make_shared<const DeviceBvh>(*tree);
    tracer.trace_gpu = [d_tree, variant](Query query, const RayF* d_rays, int count,
                                         MeshHit* d_hits) {
      trace_rays_gpu(query, variant, d_tree->view(), d_rays, count, d_hits);
    };
    tracer.registers = [variant](Query query) {
      return trace_kernel_registers(query, variant);
    };
  }
  return tracer;
}

std::vector<Tracer> chapter07_tracers(const TracerScene& scene) {
  return {bvh_tracer(to_string(scene.bvh.options.method), scene.bvh, scene)};
}

Tracer brute_force_tracer(const TracerScene& scene) {
  Tracer tracer;
  tracer.name = "brute force (chapter 04)";
  tracer.rule = HitRule::ties_allowed; // it tests the triangles in file order, not tree order
  tracer.slow = true;
  tracer.bytes_per_triangle =
      double(scene.mesh.vertices.size() * sizeof(Vec3f) +
             scene.mesh.triangles.size() * sizeof(ch04::IndexedTriangle)) /
      double(std::max<std::size_t>(1, scene.mesh.triangles.size()));
  if (scene.backend != Backend::gpu) return tracer;
  struct DeviceMesh {
    DeviceBuffer<Vec3f> vertices;
    DeviceBuffer<ch04::IndexedTriangle> triangles;
  };
  const auto d_mesh = std::make_shared<const DeviceMesh>(
      DeviceMesh{DeviceBuffer<Vec3f>(std::span<const Vec3f>(scene.mesh.vertices)),
                 DeviceBuffer<ch04::IndexedTriangle>(
                     std::span<const ch04::IndexedTriangle>(scene.mesh.triangles))});
  const TriangleVariant variant = scene.variant;
  // Closest hits answer any-hit queries too: "hit or not" is all an any-hit query compares.
  tracer.trace_gpu = [d_mesh, variant](Query, const RayF* d_rays, int count, MeshHit* d_hits) {
    brute_force_gpu(
        variant,
        {d_mesh->vertices.data(), d_mesh->triangles.data(), int(d_mesh->triangles.size())},
        d_rays, count, d_hits);
  };
  return tracer;
}

} // namespace rt::ch07
