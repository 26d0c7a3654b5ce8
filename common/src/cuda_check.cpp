// CUDA error checking (chapter 01): see rt/cuda_check.h.
#include "rt/cuda_check.h"

#include <cstdlib>
#include <cstring>
#include <string>

namespace rt {

namespace {

std::string describe(cudaError_t code, const std::string& expression, const char* file,
                     int line) {
  const char* base = std::strrchr(file, '/');
  return std::string(cudaGetErrorName(code)) + " (" + cudaGetErrorString(code) + ") in " +
         expression + " at " + (base ? base + 1 : file) + ":" + std::to_string(line);
}

} // namespace

CudaError::CudaError(cudaError_t code, const std::string& expression, const char* file,
                     int line)
    : Error(describe(code, expression, file, line)), code_(code) {}

void cuda_check(cudaError_t code, const char* expression, const char* file, int line) {
  if (code != cudaSuccess) {
    cudaGetLastError(); // clear the sticky last-error slot so later checks start clean
    throw CudaError(code, expression, file, line);
  }
}

void cuda_check_launch(const char* kernel, const char* file, int line) {
  const std::string what = std::string("launch of ") + kernel;
  cuda_check(cudaGetLastError(), what.c_str(), file, line);
  static const bool sync_each_launch = [] {
    const char* value = std::getenv("RT_SYNC_CHECK");
    return value != nullptr && std::strcmp(value, "1") == 0;
  }();
  if (sync_each_launch) cuda_check(cudaDeviceSynchronize(), what.c_str(), file, line);
}

} // namespace rt
