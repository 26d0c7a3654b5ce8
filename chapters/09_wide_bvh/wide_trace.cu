// Chapter 09: rays through a wide tree on the GPU. See wide_trace.h.
#include "wide_trace.h"

#include "rt/cuda_check.h"
#include "rt/launch.h"
#include "wide_traverse.h"

namespace rt::ch09 {
namespace {

constexpr int k_block = 128; // threads per block, as in chapters 07 and 08

// [listing:wide_kernel]
template <Query kQuery, class Node>
__global__ void wide_trace_kernel(WideTreeView<Node> tree, const RayF* rays, int count,
                                  MeshHit* hits) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  const TraceHit hit = trace_wide<kQuery>(tree, rays[i]);
  hits[i] = {hit.t, hit.triangle};
}
// [/listing:wide_kernel]

template <class Node, class Fn> void with_wide_kernel(Query query, Fn fn) {
  if (query == Query::closest)
    fn(wide_trace_kernel<Query::closest, Node>);
  else
    fn(wide_trace_kernel<Query::any, Node>);
}

} // namespace

template <class Node>
void trace_wide_gpu(Query query, const WideTreeView<Node>& tree, const RayF* rays, int count,
                    MeshHit* hits) {
  if (count <= 0) return;
  with_wide_kernel<Node>(query, [&](auto kernel) {
    kernel<<<blocks_to_cover(count, k_block), k_block>>>(tree, rays, count, hits);
  });
  RT_CUDA_CHECK_LAUNCH("wide_trace_kernel");
}

template <class Node> int wide_kernel_registers(Query query) {
  cudaFuncAttributes attributes{};
  with_wide_kernel<Node>(
      query, [&](auto kernel) { RT_CUDA_CHECK(cudaFuncGetAttributes(&attributes, kernel)); });
  return attributes.numRegs;
}

#define RT_CH09_GPU_LAYOUT(Node)                                                               \
  template void trace_wide_gpu<Node>(Query, const WideTreeView<Node>&, const RayF*, int,       \
                                     MeshHit*);                                                \
  template int wide_kernel_registers<Node>(Query);
RT_CH09_GPU_LAYOUT(WideNode<4>)
RT_CH09_GPU_LAYOUT(WideNode<8>)
RT_CH09_GPU_LAYOUT(CompressedNode)
#undef RT_CH09_GPU_LAYOUT

} // namespace rt::ch09
