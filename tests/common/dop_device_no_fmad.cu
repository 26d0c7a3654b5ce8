// difference_of_products on the GPU built with --fmad=false (no FMA contraction).
#include "dop_device.cuh"

std::vector<float> dop_on_gpu_no_fmad(const std::vector<float>& quads) {
  return rt::testing::dop_on_gpu(quads);
}
