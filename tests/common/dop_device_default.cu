// difference_of_products on the GPU with nvcc's default flags (FMA contraction on).
#include "dop_device.cuh"

std::vector<float> dop_on_gpu_default_flags(const std::vector<float>& quads) {
  return rt::testing::dop_on_gpu(quads);
}
