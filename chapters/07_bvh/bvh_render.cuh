// Chapter 07: the shaded-frame kernel for a scene traced through any tree type the traversal
// accepts. Included by the .cu file that instantiates it (this chapter's bvh_render.cu, and
// later chapters' own trees); CUDA code, so only for nvcc.
#pragma once

#include "bvh_scene.h"
#include "feature_sets.h"
#include "rt/backend.h"
#include "rt/cuda_check.h"
#include "rt/error.h"
#include "rt/launch.h"
#include "shaded_frame.h"

namespace rt::ch07 {

template <class S, class F>
__global__ void bvh_shade_kernel(ch06::FrameLaunchOf<S> frame, F features) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x;
  const int y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x < frame.extent.width && y < frame.extent.height)
    ch06::shade_pixel(frame, features, x, y);
}

// A shaded frame of `scene` (device pointers on the GPU backend, host pointers on the CPU),
// by a kernel specialised on the frame's features; records and radiance as chapter 06's
// render_shaded writes them, where not null.
template <class S>
void render_shaded_through(Backend backend, unsigned features, const S& scene,
                           const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                           ch06::ShadedPixelRecord* records, Vec3f* radiance = nullptr) {
  const ch06::FrameLaunchOf<S> frame{scene, camera, extent, pixels, records, radiance};
  ch06::with_specialised(features, [&](auto specialised) {
    if (backend == Backend::cpu) {
      for_each_pixel_cpu(extent,
                         [&](int x, int y) { ch06::shade_pixel(frame, specialised, x, y); });
      return;
    }
    if (backend != Backend::gpu) throw Error("render_shaded: resolve the backend first");
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
