// Chapter 11: an array in the memory of a backend: host memory for the CPU, device memory for
// the GPU. The path tracer keeps its running sums, its counters and the wavefront's queues in
// them, so that one renderer serves both backends with the same stage functions.
#pragma once

#include <cstring>
#include <vector>

#include "rt/backend.h"
#include "rt/device_buffer.h"

namespace rt::ch11 {

template <class T> class BackendArray {
public:
  BackendArray() = default;
  BackendArray(Backend backend, std::size_t count) : backend_(backend) {
    if (backend == Backend::gpu)
      device_ = DeviceBuffer<T>(count);
    else
      host_.resize(count);
  }
  T* data() { return backend_ == Backend::gpu ? device_.data() : host_.data(); }
  const T* data() const { return backend_ == Backend::gpu ? device_.data() : host_.data(); }
  std::size_t size() const { return backend_ == Backend::gpu ? device_.size() : host_.size(); }
  void clear() { // every byte zero
    if (backend_ == Backend::gpu)
      device_.fill_bytes(0);
    else if (!host_.empty())
      std::memset(static_cast<void*>(host_.data()), 0, host_.size() * sizeof(T));
  }
  std::vector<T> to_host() const {
    return backend_ == Backend::gpu ? device_.to_host() : host_;
  }

private:
  Backend backend_ = Backend::cpu;
  std::vector<T> host_;
  DeviceBuffer<T> device_;
};

} // namespace rt::ch11
