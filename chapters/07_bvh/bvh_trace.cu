// Chapter 07: batches of rays through the tree. See bvh_trace.h.
#include "bvh_trace.h"

#include <algorithm>
#include <string>

#include "model_render.h"
#include "rt/cuda_check.h"
#include "rt/error.h"
#include "rt/kernel_info.h"
#include "rt/launch.h"

namespace rt::ch07 {
namespace {

constexpr int k_block = 128; // threads per block of the 1D ray kernels

// [listing:trace_kernel]
template <Query kQuery, TriangleVariant kVariant>
__global__ void trace_kernel(BvhView bvh, const RayF* rays, int count, MeshHit* hits) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  const TraceHit hit = trace_bvh<kQuery, kVariant>(bvh, rays[i]);
  hits[i] = {hit.t, hit.triangle};
}
// [/listing:trace_kernel]

template <TriangleVariant kVariant>
__global__ void brute_force_kernel(ch04::MeshView mesh, const RayF* rays, int count,
                                   MeshHit* hits) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < count) hits[i] = ch04::closest_hit(kVariant, mesh, rays[i]);
}

// Calls fn(kernel) with the instantiation for a query and a variant.
template <class Fn>
decltype(auto) with_trace_kernel(Query query, TriangleVariant variant, Fn fn) {
  using V = TriangleVariant;
  if (query == Query::closest)
    return variant == V::watertight ? fn(trace_kernel<Query::closest, V::watertight>)
                                    : fn(trace_kernel<Query::closest, V::moller_trumbore>);
  return variant == V::watertight ? fn(trace_kernel<Query::any, V::watertight>)
                                  : fn(trace_kernel<Query::any, V::moller_trumbore>);
}

} // namespace

const char* to_string(Query query) { return query == Query::closest ? "closest" : "any"; }

DeviceBvh::DeviceBvh(const Bvh& bvh)
    : nodes_(std::span<const BvhNode>(bvh.nodes)),
      triangles_(std::span<const TriangleF>(bvh.triangles)),
      ids_(std::span<const int>(bvh.triangle_ids)) {}

BvhView DeviceBvh::view() const {
  return {nodes_.data(), triangles_.data(), ids_.data(), static_cast<int>(nodes_.size())};
}

void trace_rays_gpu(Query query, TriangleVariant variant, const BvhView& bvh, const RayF* rays,
                    int count, MeshHit* hits) {
  if (count <= 0) return;
  with_trace_kernel(query, variant, [&](auto kernel) {
    kernel<<<blocks_to_cover(count, k_block), k_block>>>(bvh, rays, count, hits);
  });
  RT_CUDA_CHECK_LAUNCH("trace_kernel");
}

int trace_kernel_registers(Query query, TriangleVariant variant) {
  int registers = 0;
  with_trace_kernel(query, variant, [&](auto kernel) { registers = kernel_registers(kernel); });
  return registers;
}

void brute_force_gpu(TriangleVariant variant, const ch04::MeshView& mesh, const RayF* rays,
                     int count, MeshHit* hits) {
  if (count <= 0) return;
  const int blocks = blocks_to_cover(count, k_block);
  if (variant == TriangleVariant::watertight)
    brute_force_kernel<TriangleVariant::watertight>
        <<<blocks, k_block>>>(mesh, rays, count, hits);
  else
    brute_force_kernel<TriangleVariant::moller_trumbore>
        <<<blocks, k_block>>>(mesh, rays, count, hits);
  RT_CUDA_CHECK_LAUNCH("brute_force_kernel");
}

void trace_rays_cpu(Query query, TriangleVariant variant, const BvhView& bvh,
                    std::span<const RayF> rays, std::span<MeshHit> hits) {
  if (hits.size() != rays.size()) throw Error("trace_rays_cpu: one hit per ray");
  for_each_ray_cpu(rays.size(), [&](std::size_t i) {
    const TraceHit hit = query == Query::closest
                             ? trace_bvh<Query::closest>(variant, bvh, rays[i])
                             : trace_bvh<Query::any>(variant, bvh, rays[i]);
    hits[i] = {hit.t, hit.triangle};
  });
}

std::vector<MeshHit> trace_rays(Backend backend, Query query, TriangleVariant variant,
                                const Bvh& bvh, std::span<const RayF> rays) {
  std::vector<MeshHit> hits(rays.size());
  if (backend == Backend::cpu) {
    trace_rays_cpu(query, variant, bvh.view(), rays, hits);
    return hits;
  }
  ch05::check_device_memory(bvh.nodes.size() * sizeof(BvhNode) +
                                bvh.triangles.size() * (sizeof(TriangleF) + sizeof(int)) +
                                rays.size() * (sizeof(RayF) + sizeof(MeshHit)),
                            "the tree and the ray batch");
  const DeviceBvh d_bvh(bvh);
  const DeviceBuffer<RayF> d_rays(rays);
  DeviceBuffer<MeshHit> d_hits(rays.size());
  trace_rays_gpu(query, variant, d_bvh.view(), d_rays.data(), static_cast<int>(rays.size()),
                 d_hits.data());
  d_hits.download(hits);
  return hits;
}

std::vector<std::size_t> every_kth_index(std::size_t total, long long count) {
  std::vector<std::size_t> out;
  if (total == 0 || count <= 0) return out;
  const std::size_t step = std::max<std::size_t>(1, total / static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < total; i += step) out.push_back(i);
  return out;
}

HitAgreement compare_hits(std::span<const MeshHit> hits, std::span<const MeshHit> reference) {
  if (hits.size() != reference.size()) throw Error("compare_hits: the lists differ in length");
  HitAgreement a;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const MeshHit h = hits[i], r = reference[i];
    if (r.triangle >= 0) ++a.hits;
    if (h.triangle == r.triangle && (r.triangle < 0 || h.t == r.t)) continue;
    if (h.triangle >= 0 && r.triangle >= 0 && h.t == r.t)
      ++a.ties;
    else
      ++a.mismatches;
  }
  return a;
}

TraversalWork measure_work(Query query, TriangleVariant variant, const BvhView& bvh,
                           std::span<const RayF> rays) {
  const CpuWorkName work("counting the traversal's work");
  CpuProgress progress(static_cast<long long>(rays.size()), "rays");
  long long done = 0;
  return average_work(rays, [&](const RayF& ray, Counters& c) {
    progress.update(done++);
    if (query == Query::closest)
      trace_bvh<Query::closest>(variant, bvh, ray, c);
    else
      trace_bvh<Query::any>(variant, bvh, ray, c);
  });
}

} // namespace rt::ch07
