// Chapter 07: shaded frames through the tree. See bvh_render.h.
#include "bvh_render.h"

#include "feature_sets.h"
#include "rt/cuda_check.h"
#include "rt/error.h"
#include "rt/launch.h"

namespace rt::ch07 {
namespace {

using Frame = ch06::FrameLaunchOf<BvhSceneView>;

template <class F> __global__ void bvh_shade_kernel(Frame frame, F features) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x;
  const int y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x < frame.extent.width && y < frame.extent.height)
    ch06::shade_pixel(frame, features, x, y);
}

} // namespace

void render_bvh_shaded(Backend backend, unsigned features, const BvhSceneView& scene,
                       const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                       ch06::ShadedPixelRecord* records) {
  const Frame frame{scene, camera, extent, pixels, records};
  ch06::with_specialised(features, [&](auto specialised) {
    if (backend == Backend::cpu) {
      for_each_pixel_cpu(extent,
                         [&](int x, int y) { ch06::shade_pixel(frame, specialised, x, y); });
      return;
    }
    if (backend != Backend::gpu) throw Error("render_bvh_shaded: resolve the backend first");
    if (extent.width <= 0 || extent.height <= 0) return;
    const BlockShape block;
    const dim3 threads(block.x, block.y);
    const dim3 grid(blocks_to_cover(extent.width, block.x),
                    blocks_to_cover(extent.height, block.y));
    bvh_shade_kernel<<<grid, threads>>>(frame, specialised);
    RT_CUDA_CHECK_LAUNCH("bvh_shade_kernel");
  });
}

} // namespace rt::ch07
