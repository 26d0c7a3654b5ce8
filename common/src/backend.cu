// Backend selection (chapter 01): see rt/backend.h.
#include "rt/backend.h"

#include <algorithm>
#include <cstdlib>
#include <ostream>
#include <string>
#include <thread>

#include <cuda_runtime.h>

#include "rt/error.h"

namespace rt {

namespace {

// An empty kernel: asking for its attributes tells whether this build carries machine code
// (or PTX) that the present GPU can run.
__global__ void probe_kernel() {}

std::string cuda_reason(cudaError_t code) {
  return std::string(cudaGetErrorName(code)) + ": " + cudaGetErrorString(code);
}

GpuInfo probe() {
  GpuInfo info;
  int count = 0;
  cudaError_t code = cudaGetDeviceCount(&count);
  if (code != cudaSuccess || count == 0) {
    info.why_unusable = code != cudaSuccess ? cuda_reason(code) : "no CUDA device found";
    cudaGetLastError();
    return info;
  }
  cudaDeviceProp prop{};
  code = cudaGetDeviceProperties(&prop, 0);
  if (code == cudaSuccess) {
    info.name = prop.name;
    info.compute_capability = prop.major * 10 + prop.minor;
    info.multiprocessors = prop.multiProcessorCount;
  }
  if (code == cudaSuccess) code = cudaSetDevice(0);
  if (code == cudaSuccess) code = cudaFree(nullptr); // creates the context
  cudaFuncAttributes attributes{};
  if (code == cudaSuccess) code = cudaFuncGetAttributes(&attributes, probe_kernel);
  if (code != cudaSuccess) {
    info.why_unusable = cuda_reason(code);
    if (code == cudaErrorNoKernelImageForDevice || code == cudaErrorInvalidDeviceFunction)
      info.why_unusable += " (this build has no code for " + info.name + ", sm_" +
                           std::to_string(info.compute_capability) +
                           "; rebuild with -DCMAKE_CUDA_ARCHITECTURES=native)";
    cudaGetLastError();
    return info;
  }
  info.usable = true;
  return info;
}

} // namespace

const char* to_string(Backend backend) {
  switch (backend) {
  case Backend::automatic:
    return "auto";
  case Backend::gpu:
    return "gpu";
  case Backend::cpu:
    return "cpu";
  }
  return "?";
}

Backend parse_backend(std::string_view text) {
  if (text == "auto") return Backend::automatic;
  if (text == "gpu") return Backend::gpu;
  if (text == "cpu") return Backend::cpu;
  throw UsageError("unknown backend '" + std::string(text) + "' (expected auto, gpu or cpu)");
}

const GpuInfo& gpu_info() {
  static const GpuInfo info = probe();
  return info;
}

Backend resolve_backend(Backend requested, std::ostream& notice) {
  if (requested == Backend::cpu) return Backend::cpu;
  const GpuInfo& gpu = gpu_info();
  if (gpu.usable) return Backend::gpu;
  if (requested == Backend::gpu)
    throw NoGpuError("--backend gpu: no usable CUDA device (" + gpu.why_unusable + ")");
  notice << "notice: no usable CUDA device (" << gpu.why_unusable << "); running on "
         << cpu_thread_count() << " CPU threads\n";
  return Backend::cpu;
}

std::vector<Backend> report_backends(Backend resolved, bool skip_cpu) {
  std::vector<Backend> backends{resolved};
  if (resolved == Backend::gpu && !skip_cpu) backends.push_back(Backend::cpu);
  return backends;
}

int cpu_thread_count() {
  static const int count = [] {
    if (const char* env = std::getenv("RT_CPU_THREADS")) {
      const int n = std::atoi(env);
      if (n > 0) return std::min(n, 1024);
    }
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  }();
  return count;
}

std::string describe_backend(Backend resolved) {
  if (resolved == Backend::gpu) return gpu_info().name;
  return std::to_string(cpu_thread_count()) + " CPU threads";
}

} // namespace rt
