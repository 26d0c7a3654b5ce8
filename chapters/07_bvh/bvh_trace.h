// Chapter 07: batches of rays through the tree on either backend. The GPU kernel is the
// benchmark's "traversal kernel": one thread per ray, rays in and hits out, nothing else.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <span>
#include <thread>
#include <vector>

#include "bvh.h"
#include "rt/backend.h"
#include "rt/cpu_progress.h"
#include "rt/device_buffer.h"
#include "rt/launch.h"
#include "rt/timer.h"
#include "traverse.h"

namespace rt::ch07 {

// A tree copied to the GPU, owned.
class DeviceBvh {
public:
  explicit DeviceBvh(const Bvh& bvh);
  BvhView view() const;
  std::size_t bytes() const { return nodes_.bytes() + triangles_.bytes() + ids_.bytes(); }

private:
  DeviceBuffer<BvhNode> nodes_;
  DeviceBuffer<TriangleF> triangles_;
  DeviceBuffer<int> ids_;
};

// Traces `count` rays (device memory) into `hits` (device memory): closest or any hit.
void trace_rays_gpu(Query query, TriangleVariant variant, const BvhView& bvh, const RayF* rays,
                    int count, MeshHit* hits);

// Runs fn(i) for every ray index i in 0 .. count-1 on `threads` CPU threads: the 1-D launch
// helper of rt/launch.h, which hands out chunks of rays from a shared counter.
template <class Fn>
void for_each_ray_cpu(std::size_t count, Fn fn, int threads = cpu_thread_count()) {
  for_each_index_cpu(count, fn, threads, "rays");
}

// The same on CPU cores (host memory), through the same RT_HD traversal.
void trace_rays_cpu(Query query, TriangleVariant variant, const BvhView& bvh,
                    std::span<const RayF> rays, std::span<MeshHit> hits);

// Host rays in, host hits out, on the resolved backend (uploads on the GPU).
std::vector<MeshHit> trace_rays(Backend backend, Query query, TriangleVariant variant,
                                const Bvh& bvh, std::span<const RayF> rays);

// Brute force (every ray against every triangle), chapter 04's closest_hit, on the GPU: the
// row the tree is measured against. Device memory in and out.
void brute_force_gpu(TriangleVariant variant, const ch04::MeshView& mesh, const RayF* rays,
                     int count, MeshHit* hits);

// About `count` evenly spaced indices of 0 .. total-1 (every k-th, k = total / count): the
// sample of a batch that a slower reference (brute force, float64) traces. Empty when either
// is zero.
std::vector<std::size_t> every_kth_index(std::size_t total, long long count);

// Two hit lists of the same rays compared: a tie is the same distance on another triangle
// (which of the two a search keeps depends on the order it tests them in); anything else
// that differs is a mismatch.
struct HitAgreement {
  long long mismatches = 0;
  long long ties = 0;
  long long hits = 0; // of `reference`
};
HitAgreement compare_hits(std::span<const MeshHit> hits, std::span<const MeshHit> reference);

// Average work per ray over a batch (CPU, with counters): what the tree saves.
struct TraversalWork {
  double nodes_per_ray = 0.0;
  double triangles_per_ray = 0.0;
  int max_stack = 0;
};
TraversalWork measure_work(Query query, TriangleVariant variant, const BvhView& bvh,
                           std::span<const RayF> rays);

// The same for any traversal: trace(ray, counters) traces one ray with chapter 07's counters;
// the counts are averaged over the batch.
template <class Trace> TraversalWork average_work(std::span<const RayF> rays, Trace&& trace) {
  long long nodes = 0, triangles = 0;
  int max_stack = 0;
  for (const RayF& ray : rays) {
    Counters c;
    trace(ray, c);
    nodes += c.nodes;
    triangles += c.triangles;
    max_stack = std::max(max_stack, c.max_stack);
  }
  const double n = rays.empty() ? 1.0 : double(rays.size());
  return {double(nodes) / n, double(triangles) / n, max_stack};
}

// Registers per thread of the traversal kernel (cudaFuncGetAttributes); needs a usable GPU.
int trace_kernel_registers(Query query, TriangleVariant variant);

} // namespace rt::ch07
