// Chapter 11: the three ways of running paths (the megakernel, persistent threads and the
// wavefront stages) as templates over the scene's view S and the kernel's features F. S brings
// its path type (S::Path, at least a PathState) and the functions a path needs, found by S's
// type: start_path(s, camera, x, y, sample) and shade_vertex(s, features, strategy, path, hit,
// shadows). This chapter instantiates them for PathSceneView (path_render.cu); a
// later chapter with other surfaces instantiates the same code for its own view.
#pragma once

#include <algorithm>

#include "path_trace.h"
#include "rt/backend_array.h"
#include "rt/cuda_check.h"
#include "rt/kernel_info.h"
#include "rt/launch.h"
#include "shaded_render.h"

namespace rt::ch11 {

// [listing:megakernel_pixel]
// One pixel of the megakernel: its samples one after another, each added to the running sum.
template <class S, class F> struct MegakernelPixel {
  S scene;
  F features;
  Strategy strategy;
  ch03::Camera<float> camera;
  unsigned first_sample;
  int samples;
  float4* sums;
  unsigned* non_finite;

  RT_HD void operator()(int x, int y) const {
    const int index = y * camera.pinhole.width + x;
    float4 sum = sums[index];
    for (int s = 0; s < samples; ++s)
      add_sample(
          sum, trace_path(scene, features, strategy, camera, x, y, first_sample + unsigned(s)),
          non_finite);
    sums[index] = sum;
  }
};
// [/listing:megakernel_pixel]

template <class S, class F>
void run_megakernel(Backend backend, F features, Strategy strategy, const S& scene,
                    const ch03::Camera<float>& camera, unsigned first_sample, int samples,
                    float4* sums, unsigned* non_finite) {
  const Extent extent{camera.pinhole.width, camera.pinhole.height};
  for_each_pixel(backend, extent,
                 MegakernelPixel<S, F>{scene, features, strategy, camera, first_sample, samples,
                                       sums, non_finite});
}

#ifdef __CUDACC__
// [listing:persistent_paths]
// The persistent megakernel (Aila & Laine 2009's persistent threads, with the path
// regeneration of Novak et al. 2010). In the megakernel a warp runs until the longest of its
// 32 paths ends, the lanes of the shorter ones idle; here a lane whose path ended takes the
// next one. The lanes that need a path take them together, one atomic per warp; paths are
// numbered in tiles of pixels, a warp's worth each, so that a warp's camera rays start
// coherent. One sample per launch: each pixel's sum gets one path, in sample order as in the
// megakernel.
inline constexpr unsigned k_warp_lanes = 32;
static_assert(PixelTiles::k_width * PixelTiles::k_height == k_warp_lanes,
              "a tile is one warp's paths");

template <class S, class F>
__global__ void persistent_paths_kernel(S scene, F features, Strategy strategy,
                                        ch03::Camera<float> camera, unsigned sample,
                                        float4* sums, unsigned* non_finite,
                                        unsigned* next_path) {
  const PixelTiles tiles(camera.pinhole.width, camera.pinhole.height);
  const unsigned paths = unsigned(tiles.count());
  const unsigned lane = threadIdx.x % k_warp_lanes;
  typename S::Path path{};
  bool alive = false;
  for (;;) {
    const unsigned active = __activemask();
    const unsigned idle = __ballot_sync(active, !alive);
    if (idle != 0) {
      const int leader = __ffs(int(idle)) - 1;
      unsigned first = 0;
      if (int(lane) == leader) first = atomicAdd(next_path, unsigned(__popc(int(idle))));
      first = __shfl_sync(active, first, leader);
      if (!alive) {
        const unsigned index = first + unsigned(__popc(int(idle & ((1u << lane) - 1u))));
        if (index >= paths) break; // every path is taken
        int x = 0, y = 0;
        if (!tiles.pixel(index, x, y)) continue; // a tile's part outside the image
        path = start_path(scene, camera, x, y, sample);
        alive = true;
      }
    }
    alive = extend_path(scene, features, strategy, path);
    if (!alive) {
      float4 sum = sums[path.pixel];
      add_sample(sum, path.radiance, non_finite);
      sums[path.pixel] = sum;
    }
  }
}
// [/listing:persistent_paths]

// Blocks of the persistent kernel: as many as the GPU keeps resident at once.
inline constexpr int k_persistent_threads = 128;

// The persistent threads' samples; on the CPU, the megakernel's.
template <class S, class F>
void run_persistent(Backend backend, F features, Strategy strategy, const S& scene,
                    const ch03::Camera<float>& camera, unsigned first_sample, int samples,
                    float4* sums, unsigned* non_finite, unsigned* next_path) {
  if (backend == Backend::cpu)
    return run_megakernel(backend, features, strategy, scene, camera, first_sample, samples,
                          sums, non_finite);
  const int blocks = resident_blocks(persistent_paths_kernel<S, F>, k_persistent_threads);
  for (int s = 0; s < samples; ++s) {
    RT_CUDA_CHECK(cudaMemsetAsync(next_path, 0, sizeof(unsigned)));
    persistent_paths_kernel<S, F><<<blocks, k_persistent_threads>>>(
        scene, features, strategy, camera, first_sample + unsigned(s), sums, non_finite,
        next_path);
    RT_CUDA_CHECK_LAUNCH("persistent_paths_kernel");
  }
}

// Registers per thread of the megakernel's GPU kernel (or the persistent one's).
template <class S, class F> int megakernel_registers_of(bool persistent) {
  return persistent ? kernel_registers(persistent_paths_kernel<S, F>)
                    : kernel_registers(for_each_pixel_kernel<MegakernelPixel<S, F>>);
}
#endif // __CUDACC__

} // namespace rt::ch11
