// Chapter 07: the benchmark protocol's rays on the GPU. This file, and only this one of the
// chapter, is compiled with -fmad=false (CMakeLists.txt), and it alone gives protocol.h's
// functions a device side (RT_NO_CONTRACTION, cosine_sampling.h): every multiply and add is
// rounded on its own, as on the CPU, so both backends make the same rays bit for bit.
#define RT_NO_CONTRACTION 1
#include "protocol.h"

#include <algorithm>
#include <cstddef>

#include <cub/device/device_select.cuh>
#include <thrust/iterator/counting_iterator.h>

#include "ray_batch.h"
#include "rt/device_buffer.h"
#include "rt/error.h"
#include "rt/launch.h"

namespace rt::ch07 {

void camera_rays_gpu(const PinholeCamera& camera, RayF* d_rays) {
  const int width = camera.width;
  for_each_pixel_gpu(Extent{camera.width, camera.height}, [=] __device__(int i, int j) {
    d_rays[j * width + i] = camera_ray(camera, i, j);
  });
}

namespace {

// CUB's selection test: did this pixel's primary ray hit a triangle of the mesh? The bounds
// check keeps a corrupt id from reading outside the mesh.
struct PrimaryHitAt {
  const MeshHit* hits;
  int triangle_count;

  __device__ bool operator()(int pixel) const {
    const int triangle = hits[pixel].triangle;
    return triangle >= 0 && triangle < triangle_count;
  }
};

} // namespace

int secondary_rays_gpu(RayType type, ch04::MeshView d_mesh, const MeshHit* d_primary_hits,
                       const PinholeCamera& camera, float scene_radius, RayF* d_rays,
                       int* d_pixels) {
  if (type == RayType::primary)
    throw Error("secondary_rays_gpu: primary rays come from the camera, not from hits");
  const int pixel_count = camera.width * camera.height;
  if (pixel_count <= 0) return 0;

  // 1. The numbers of the hit pixels, compacted in increasing order. A stream compaction
  // (a prefix sum over the hit flags, then a scatter) keeps the order, where an atomic
  // counter would hand out slots in whatever order the threads happen to run.
  const thrust::counting_iterator<int> all_pixels(0);
  const PrimaryHitAt is_hit{d_primary_hits, d_mesh.triangle_count};
  DeviceBuffer<int> d_count(1);
  std::size_t temp_bytes = 0;
  RT_CUDA_CHECK(cub::DeviceSelect::If(nullptr, temp_bytes, all_pixels, d_pixels, d_count.data(),
                                      pixel_count, is_hit));
  // A null scratch pointer asks CUB for the size again: allocate at least one byte.
  DeviceBuffer<unsigned char> d_temp(std::max<std::size_t>(temp_bytes, 1));
  RT_CUDA_CHECK(cub::DeviceSelect::If(d_temp.data(), temp_bytes, all_pixels, d_pixels,
                                      d_count.data(), pixel_count, is_hit));
  RT_CUDA_CHECK_LAUNCH("cub::DeviceSelect::If");
  int count = 0;
  RT_CUDA_CHECK(cudaMemcpy(&count, d_count.data(), sizeof(int), cudaMemcpyDeviceToHost));

  // 2. One thread per hit pixel makes its ray.
  const int width = camera.width;
  ch03::for_each_ray_gpu(count, [=] __device__(int k) {
    const int p = d_pixels[k];
    const int i = p % width, j = p / width;
    const MeshHit hit = d_primary_hits[p];
    d_rays[k] = secondary_ray(type, camera_ray(camera, i, j), hit,
                              d_mesh.triangle(hit.triangle), i, j, scene_radius);
  });
  return count;
}

} // namespace rt::ch07
