// Chapter 03: a batch of independent rays on either backend: one GPU thread per ray, or rows
// of rays handed to CPU threads by the launch helper of chapter 01.
#pragma once

#include "rt/launch.h"

namespace rt::ch03 {

// Runs fn(i) for every ray index i in [0, count) on all CPU cores.
template <class RayFn> void for_each_ray_cpu(int count, RayFn fn) {
  constexpr int k_rays_per_row = 1024; // a row is the unit of work a CPU thread takes
  const Extent rows{k_rays_per_row, blocks_to_cover(count, k_rays_per_row)};
  for_each_pixel_cpu(rows, [&](int x, int y) {
    const int i = y * k_rays_per_row + x;
    if (i < count) fn(i); // the last row is only partly filled
  });
}

#if RT_DEVICE_CODE_POSSIBLE
template <class RayFn> __global__ void for_each_ray_kernel(int count, RayFn fn) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < count) fn(i);
}

// Runs the device lambda fn(i) for every ray index, one thread each.
template <class RayFn> void for_each_ray_gpu(int count, RayFn fn) {
  constexpr int k_threads_per_block = 256;
  if (count <= 0) return;
  for_each_ray_kernel<<<blocks_to_cover(count, k_threads_per_block), k_threads_per_block>>>(
      count, fn);
  RT_CUDA_CHECK_LAUNCH("for_each_ray_kernel");
}
#endif

} // namespace rt::ch03
