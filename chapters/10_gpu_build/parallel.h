// Chapter 10: the two tools every pass of the GPU build is written with. rt::for_each_index
// (rt/launch.h) runs one RT_HD function per item, as a CUDA kernel or on CPU threads, and
// rt::BackendArray holds a pass's data in device or host memory, whichever the backend reads.
// Only .cu files include this header: the GPU side needs nvcc.
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
