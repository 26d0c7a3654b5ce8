// difference_of_products evaluated on the GPU. Included by two .cu files: one built with
// nvcc's default FMA contraction, one with --fmad=false.
#pragma once

#include <vector>

#include "rt/device_buffer.h"
#include "rt/scalar.h"

namespace rt::testing {

template <class T> __global__ void dop_kernel(const T* in, T* out, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n)
    out[i] = difference_of_products(in[4 * i], in[4 * i + 1], in[4 * i + 2], in[4 * i + 3]);
}

template <class T> std::vector<T> dop_on_gpu(const std::vector<T>& quads) {
  const int n = static_cast<int>(quads.size() / 4);
  DeviceBuffer<T> d_in{std::span<const T>(quads)};
  DeviceBuffer<T> d_out(n);
  dop_kernel<<<(n + 255) / 256, 256>>>(d_in.data(), d_out.data(), n);
  RT_CUDA_CHECK_LAUNCH("dop_kernel");
  return d_out.to_host();
}

} // namespace rt::testing
