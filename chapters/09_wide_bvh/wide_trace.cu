// Chapter 09: rays through a wide tree on the GPU. See wide_trace.h.
#include "wide_trace.h"

#include "rt/cuda_check.h"
#include "rt/launch.h"
#include "wide_traverse.h"

namespace rt::ch09 {
namespace {

constexpr int k_block = 128; // threads per block, as in chapters 07 and 08

// [listing:wide_kernel]
template <Query kQuery, class View>
__global__ void wide_trace_kernel(View tree, const RayF* rays, int count, MeshHit* hits) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  const TraceHit hit = trace_wide<kQuery>(tree, rays[i]);
  hits[i] = {hit.t, hit.triangle};
}
// [/listing:wide_kernel]

template <class View, class Fn> void with_wide_kernel(Query query, Fn fn) {
  if (query == Query::closest)
    fn(wide_trace_kernel<Query::closest, View>);
  else
    fn(wide_trace_kernel<Query::any, View>);
}

} // namespace

template <class View>
void trace_wide_gpu(Query query, const View& tree, const RayF* rays, int count, MeshHit* hits) {
  if (count <= 0) return;
  with_wide_kernel<View>(query, [&](auto kernel) {
    kernel<<<blocks_to_cover(count, k_block), k_block>>>(tree, rays, count, hits);
  });
  RT_CUDA_CHECK_LAUNCH("wide_trace_kernel");
}

template <class View> int wide_kernel_registers(Query query) {
  cudaFuncAttributes attributes{};
  with_wide_kernel<View>(
      query, [&](auto kernel) { RT_CUDA_CHECK(cudaFuncGetAttributes(&attributes, kernel)); });
  return attributes.numRegs;
}

#define RT_CH09_GPU_LAYOUT(View)                                                               \
  template void trace_wide_gpu<View>(Query, const View&, const RayF*, int, MeshHit*);          \
  template int wide_kernel_registers<View>(Query);
RT_CH09_GPU_LAYOUT(Wide4Bvh::View)
RT_CH09_GPU_LAYOUT(Wide8Bvh::View)
RT_CH09_GPU_LAYOUT(CompressedBvh::View)
RT_CH09_GPU_LAYOUT(Wide4PackedBvh::View)
#undef RT_CH09_GPU_LAYOUT

} // namespace rt::ch09
