// CUDA error checking: every runtime call goes through RT_CUDA_CHECK, every kernel launch is
// followed by RT_CUDA_CHECK_LAUNCH. A failure throws rt::CudaError carrying the error's name
// (cudaErrorMemoryAllocation, ...), its message, the expression and file:line.
#pragma once

#include <string>

#include <cuda_runtime_api.h>

#include "rt/error.h"

namespace rt {

class CudaError : public Error {
public:
  CudaError(cudaError_t code, const std::string& expression, const char* file, int line);
  cudaError_t code() const { return code_; }

private:
  cudaError_t code_;
};

// Throws CudaError if code is not cudaSuccess. The macros below fill in the context.
void cuda_check(cudaError_t code, const char* expression, const char* file, int line);

// After a kernel launch: reports launch-configuration errors at once (cudaGetLastError).
// With RT_SYNC_CHECK=1 in the environment it also synchronizes, so a fault inside the kernel
// is reported at its launch rather than at some later call.
void cuda_check_launch(const char* kernel, const char* file, int line);

} // namespace rt

#define RT_CUDA_CHECK(expr) ::rt::cuda_check((expr), #expr, __FILE__, __LINE__)
#define RT_CUDA_CHECK_LAUNCH(kernel_name)                                                      \
  ::rt::cuda_check_launch(kernel_name, __FILE__, __LINE__)
