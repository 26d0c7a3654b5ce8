// Chapter 10: the two tools every pass of the GPU build is written with. for_each_index runs
// one RT_HD function per item, as a CUDA kernel or on CPU threads (chapter 07's
// for_each_ray_cpu), and rt::BackendArray holds a pass's data in device or host memory,
// whichever the backend reads. Only .cu files include this header: the GPU side needs nvcc.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>

#include "bvh_trace.h"
#include "rt/backend.h"
#include "rt/backend_array.h"
#include "rt/cuda_check.h"
#include "rt/device_buffer.h"
#include "rt/launch.h"

namespace rt::ch10 {

inline constexpr int k_build_block = 256; // threads per block of the build's kernels

template <class Fn> __global__ void for_each_index_kernel(int count, Fn fn) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < count) fn(i);
}

// [listing:for_each_index]
// fn(i) for every i in 0 .. count-1: one GPU thread each, or chunks of them on CPU threads.
template <class Fn> void for_each_index(Backend backend, int count, Fn fn) {
  if (count <= 0) return;
  if (backend == Backend::cpu) {
    ch07::for_each_ray_cpu(static_cast<std::size_t>(count),
                           [&](std::size_t i) { fn(static_cast<int>(i)); });
    return;
  }
  for_each_index_kernel<<<blocks_to_cover(count, k_build_block), k_build_block>>>(count, fn);
  RT_CUDA_CHECK_LAUNCH("for_each_index_kernel");
}
// [/listing:for_each_index]

// Build time as the benchmark protocol takes it: on the GPU, CUDA events around the kernels
// (the sort included, transfers not); on the CPU, wall time.
class PassClock {
public:
  explicit PassClock(Backend backend) : backend_(backend) {
    if (backend_ == Backend::gpu) {
      start_.emplace();
      stop_.emplace();
      start_->record();
    }
    wall_start_ = std::chrono::steady_clock::now();
  }
  double milliseconds() {
    if (backend_ != Backend::gpu)
      return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                       wall_start_)
          .count();
    stop_->record();
    stop_->synchronize();
    return stop_->milliseconds_since(*start_);
  }

private:
  Backend backend_;
  std::optional<CudaEvent> start_, stop_;
  std::chrono::steady_clock::time_point wall_start_;
};

} // namespace rt::ch10
