// What the CUDA runtime says about one compiled kernel, asked through its address: the
// registers each thread holds (the reports of chapters 06-11) and the blocks the GPU keeps
// resident at once (the persistent kernels of chapters 09 and 11). CUDA only: include it from
// .cu files, and call it with a usable GPU.
#pragma once

#include <algorithm>
#include <cstddef>

#include <cuda_runtime.h>

#include "rt/cuda_check.h"

namespace rt {

// Registers per thread of `kernel`, as ptxas allocated them (cudaFuncGetAttributes).
template <class Kernel> int kernel_registers(Kernel* kernel) {
  cudaFuncAttributes attributes{};
  RT_CUDA_CHECK(cudaFuncGetAttributes(&attributes, kernel));
  return attributes.numRegs;
}

// Blocks of `block_threads` threads that the current GPU keeps resident at once: blocks per
// multiprocessor times multiprocessors. At least one per multiprocessor, so a kernel the
// occupancy calculator rates at zero (too many registers or too much shared memory for one
// block) is still launched with a grid, where its launch then names the error.
template <class Kernel>
int resident_blocks(Kernel* kernel, int block_threads, std::size_t shared_bytes = 0) {
  int device = 0, multiprocessors = 0, per_multiprocessor = 0;
  RT_CUDA_CHECK(cudaGetDevice(&device));
  RT_CUDA_CHECK(
      cudaDeviceGetAttribute(&multiprocessors, cudaDevAttrMultiProcessorCount, device));
  RT_CUDA_CHECK(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_multiprocessor, kernel,
                                                              block_threads, shared_bytes));
  return std::max(1, per_multiprocessor) * multiprocessors;
}

} // namespace rt
