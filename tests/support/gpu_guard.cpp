#include "gpu_guard.h"

#include "rt/backend.h"

namespace rt::testing {

std::string gpu_unavailable_reason() {
  const GpuInfo& gpu = gpu_info();
  return gpu.usable ? std::string() : gpu.why_unusable;
}

} // namespace rt::testing
