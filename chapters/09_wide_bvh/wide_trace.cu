// Chapter 09: rays through a wide tree on the GPU. See wide_trace.h.
#include "wide_trace.h"

#include <algorithm>
#include <cstddef>

#include <cub/device/device_radix_sort.cuh>

#include "rt/cuda_check.h"
#include "rt/kernel_info.h"
#include "rt/launch.h"
#include "wide_traverse.h"

namespace rt::ch09 {
namespace {

constexpr int k_block = 128; // threads per block, as in chapters 07 and 08

// [listing:wide_kernel]
template <Query kQuery, class View>
__global__ void wide_trace_kernel(View tree, const RayF* rays, int count, MeshHit* hits,
                                  RayOrder order) {
  int i = 0;
  if (!order.ray_of(blockIdx.x * blockDim.x + threadIdx.x, count, i)) return;
  const TraceHit hit = trace_wide<kQuery>(tree, rays[i]);
  hits[i] = {hit.t, hit.triangle};
}
// [/listing:wide_kernel]

// [listing:shared_stack]
// The stack's first kShared entries in shared memory (Ylitie et al. 2017 keep a short stack
// there), the deeper ones in a local array. Entry e of the thread with index t in its block is
// element e * kBlock + t of the block's array: a warp's 32 threads lie side by side whatever
// entry each of them touches, and since a row of kBlock entries is a multiple of the 128 bytes
// the 32 banks span, a thread's bank depends on its lane alone. So a warp's access is never
// worse than the two passes any 32 accesses of 8 bytes take, however its stacks differ in
// depth. (A slice of kShared entries side by side per thread would put lanes 64 bytes apart:
// 16 lanes on one bank.) Each thread touches its own entries only: no __syncthreads.
//
// The bound: kShared entries here and k_wide_stack_size - kShared in the spill array hold
// k_wide_stack_size together, the size proved enough in wide_bvh.h (stack_bound), whatever the
// split.
template <int kShared, int kBlock> class SharedStack {
  static_assert(0 < kShared && kShared < k_wide_stack_size);
  static_assert(kBlock * sizeof(NodeGroup) % 128 == 0, "a row of entries spans the banks");

public:
  // Launched with blocks of kBlock threads along x, so threadIdx.x < kBlock.
  __device__ SharedStack() {
    __shared__ NodeGroup first_entries[kShared * kBlock];
    shared_ = first_entries + threadIdx.x;
  }
  __device__ void store(int entry, NodeGroup group) {
    if (entry < kShared)
      shared_[entry * kBlock] = group;
    else
      spill_[entry - kShared] = group;
  }
  __device__ NodeGroup load(int entry) const {
    return entry < kShared ? shared_[entry * kBlock] : spill_[entry - kShared];
  }

private:
  NodeGroup* shared_; // this thread's entry 0; its entry e lies e * kBlock further
  NodeGroup spill_[k_wide_stack_size - kShared];
};
// [/listing:shared_stack]

// 8 entries: 8 KiB of shared memory per block of 128 threads.
constexpr int k_shared_entries = 8;
using BlockSharedStack = SharedStack<k_shared_entries, k_block>;

template <Query kQuery, class View>
__global__ void wide_shared_stack_kernel(View tree, const RayF* rays, int count,
                                         MeshHit* hits) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  const TraceHit hit = trace_wide<kQuery, BlockSharedStack>(tree, rays[i]);
  hits[i] = {hit.t, hit.triangle};
}

// [listing:persistent_kernel]
// Persistent threads (Aila and Laine 2009): the grid is only as large as the GPU holds at once,
// and each warp takes the next 32 rays from `next_ray` until none are left. Lane 0 takes them
// and the warp shares the number; `first` is the same in all 32 lanes, so the warp leaves the
// loop as one and every lane reaches each __shfl_sync (blocks are whole warps). Lanes past the
// last ray trace nothing and wait at the next one. The counter is unsigned: it passes `count`
// by at most 32 per warp, far from wrapping.
template <Query kQuery, class View>
__global__ void wide_persistent_kernel(View tree, const RayF* rays, int count, MeshHit* hits,
                                       unsigned* next_ray, RayOrder order) {
  constexpr unsigned k_all_lanes = 0xffffffffu;
  const unsigned lane = threadIdx.x % 32u;
  const unsigned numbers = unsigned(order.numbers(count));
  for (;;) {
    unsigned first = 0;
    if (lane == 0) first = atomicAdd(next_ray, 32u);
    first = __shfl_sync(k_all_lanes, first, 0);
    if (first >= numbers) return;
    int i = 0;
    if (order.ray_of(first + lane, count, i)) { // a warp's 32 numbers: one tile, when tiled
      const TraceHit hit = trace_wide<kQuery>(tree, rays[i]);
      hits[i] = {hit.t, hit.triangle};
    }
  }
}
// [/listing:persistent_kernel]

// [listing:sorted_kernels]
// The sorted batch: each ray's key and index, then (after CUB's sort) one thread per position
// in the sorted order, tracing the ray whose index sits there into that ray's own slot.
__global__ void ray_key_kernel(const RayF* rays, int count, RaySortFrame frame, unsigned* keys,
                               int* indices) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  keys[i] = ray_sort_key(rays[i], frame);
  indices[i] = i;
}

template <Query kQuery, class View>
__global__ void wide_sorted_kernel(View tree, const RayF* rays, const int* sorted_indices,
                                   int count, MeshHit* hits) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= count) return;
  const int i = sorted_indices[j];
  const TraceHit hit = trace_wide<kQuery>(tree, rays[i]);
  hits[i] = {hit.t, hit.triangle};
}
// [/listing:sorted_kernels]

template <class View, class Fn> void with_wide_kernel(Query query, Fn fn) {
  if (query == Query::closest)
    fn(wide_trace_kernel<Query::closest, View>);
  else
    fn(wide_trace_kernel<Query::any, View>);
}

template <class View, class Fn> void with_shared_stack_kernel(Query query, Fn fn) {
  if (query == Query::closest)
    fn(wide_shared_stack_kernel<Query::closest, View>);
  else
    fn(wide_shared_stack_kernel<Query::any, View>);
}

template <class View, class Fn> void with_persistent_kernel(Query query, Fn fn) {
  if (query == Query::closest)
    fn(wide_persistent_kernel<Query::closest, View>);
  else
    fn(wide_persistent_kernel<Query::any, View>);
}

template <class View, class Fn> void with_sorted_kernel(Query query, Fn fn) {
  if (query == Query::closest)
    fn(wide_sorted_kernel<Query::closest, View>);
  else
    fn(wide_sorted_kernel<Query::any, View>);
}

int query_slot(Query query) { return query == Query::closest ? 0 : 1; }

} // namespace

template <class View>
void trace_wide_gpu(Query query, const View& tree, const RayF* rays, int count, MeshHit* hits,
                    RayOrder order) {
  if (count <= 0) return;
  const int threads = static_cast<int>(order.numbers(count));
  with_wide_kernel<View>(query, [&](auto kernel) {
    kernel<<<blocks_to_cover(threads, k_block), k_block>>>(tree, rays, count, hits, order);
  });
  RT_CUDA_CHECK_LAUNCH("wide_trace_kernel");
}

template <class View> int wide_kernel_registers(Query query) {
  int registers = 0;
  with_wide_kernel<View>(query, [&](auto kernel) { registers = kernel_registers(kernel); });
  return registers;
}

template <class View>
void trace_wide_gpu_shared_stack(Query query, const View& tree, const RayF* rays, int count,
                                 MeshHit* hits) {
  if (count <= 0) return;
  with_shared_stack_kernel<View>(query, [&](auto kernel) {
    kernel<<<blocks_to_cover(count, k_block), k_block>>>(tree, rays, count, hits);
  });
  RT_CUDA_CHECK_LAUNCH("wide_shared_stack_kernel");
}

template <class View> int shared_stack_kernel_registers(Query query) {
  int registers = 0;
  with_shared_stack_kernel<View>(query,
                                 [&](auto kernel) { registers = kernel_registers(kernel); });
  return registers;
}

template <class View> PersistentWideTracer<View>::PersistentWideTracer() : next_ray_(1) {
  for (const Query query : {Query::closest, Query::any})
    with_persistent_kernel<View>(query, [&](auto kernel) {
      resident_blocks_[query_slot(query)] = resident_blocks(kernel, k_block);
    });
}

// [listing:persistent_launch]
// The counter is reset on the stream before each launch, so the reset is inside the runner's
// timed region (a 4-byte memset, next to nothing beside the trace). A batch smaller than the
// GPU gets only the blocks it needs.
template <class View>
void PersistentWideTracer<View>::trace(Query query, const View& tree, const RayF* rays,
                                       int count, MeshHit* hits, RayOrder order) {
  if (count <= 0) return;
  RT_CUDA_CHECK(cudaMemsetAsync(next_ray_.data(), 0, sizeof(unsigned)));
  const int threads = static_cast<int>(order.numbers(count));
  const int blocks =
      std::min(resident_blocks_[query_slot(query)], blocks_to_cover(threads, k_block));
  with_persistent_kernel<View>(query, [&](auto kernel) {
    kernel<<<blocks, k_block>>>(tree, rays, count, hits, next_ray_.data(), order);
  });
  RT_CUDA_CHECK_LAUNCH("wide_persistent_kernel");
}
// [/listing:persistent_launch]

template <class View> int PersistentWideTracer<View>::registers(Query query) {
  int registers = 0;
  with_persistent_kernel<View>(query,
                               [&](auto kernel) { registers = kernel_registers(kernel); });
  return registers;
}

// [listing:sorted_launch]
// Everything between the runner's timing events: the key kernel, CUB's radix sort over the
// key's 30 bits, the trace. CUB's sort is stable, so the order is the CPU's (key, then index).
// The buffers grow only when a batch is larger than any before (in the runner, during the
// warm-up launches); then each launch allocates nothing.
template <class View>
void SortedWideTracer<View>::trace(Query query, const View& tree, const RayF* rays, int count,
                                   MeshHit* hits) {
  if (count <= 0) return;
  if (keys_.size() < std::size_t(count)) {
    keys_ = DeviceBuffer<unsigned>(count);
    sorted_keys_ = DeviceBuffer<unsigned>(count);
    indices_ = DeviceBuffer<int>(count);
    sorted_indices_ = DeviceBuffer<int>(count);
  }
  std::size_t scratch_bytes = 0; // asking CUB how much scratch this count needs runs nothing
  RT_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(
      nullptr, scratch_bytes, keys_.data(), sorted_keys_.data(), indices_.data(),
      sorted_indices_.data(), count, 0, k_sort_key_bits));
  if (sort_scratch_.size() < scratch_bytes)
    sort_scratch_ = DeviceBuffer<unsigned char>(scratch_bytes);

  const int blocks = blocks_to_cover(count, k_block);
  ray_key_kernel<<<blocks, k_block>>>(rays, count, frame_, keys_.data(), indices_.data());
  RT_CUDA_CHECK_LAUNCH("ray_key_kernel");
  RT_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(
      sort_scratch_.data(), scratch_bytes, keys_.data(), sorted_keys_.data(), indices_.data(),
      sorted_indices_.data(), count, 0, k_sort_key_bits));
  with_sorted_kernel<View>(query, [&](auto kernel) {
    kernel<<<blocks, k_block>>>(tree, rays, sorted_indices_.data(), count, hits);
  });
  RT_CUDA_CHECK_LAUNCH("wide_sorted_kernel");
}
// [/listing:sorted_launch]

template <class View> int SortedWideTracer<View>::registers(Query query) {
  int registers = 0;
  with_sorted_kernel<View>(query, [&](auto kernel) { registers = kernel_registers(kernel); });
  return registers;
}

template <class View> int SortedWideTracer<View>::key_kernel_registers() {
  return kernel_registers(ray_key_kernel);
}

#define RT_CH09_GPU_LAYOUT(View)                                                               \
  template void trace_wide_gpu<View>(Query, const View&, const RayF*, int, MeshHit*,           \
                                     RayOrder);                                                \
  template int wide_kernel_registers<View>(Query);
RT_CH09_GPU_LAYOUT(Wide4Bvh::View)
RT_CH09_GPU_LAYOUT(Wide8Bvh::View)
RT_CH09_GPU_LAYOUT(CompressedBvh::View)
RT_CH09_GPU_LAYOUT(Wide4PackedBvh::View)
#undef RT_CH09_GPU_LAYOUT

template void trace_wide_gpu_shared_stack<Wide4PackedBvh::View>(Query,
                                                                const Wide4PackedBvh::View&,
                                                                const RayF*, int, MeshHit*);
template int shared_stack_kernel_registers<Wide4PackedBvh::View>(Query);
template class PersistentWideTracer<Wide4PackedBvh::View>;
template class SortedWideTracer<Wide4PackedBvh::View>;

} // namespace rt::ch09
