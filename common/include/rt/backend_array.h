// An array in the memory of a backend: host memory for the CPU, device memory for the GPU
// (chapters 10 and 11). Passes that run one RT_HD function on either backend keep their data
// in it, so the same function reads the same pointers whichever backend runs it.
#pragma once

#include <algorithm>
#include <cstring>
#include <span>
#include <vector>

#include "rt/backend.h"
#include "rt/device_buffer.h"

namespace rt {

template <class T> class BackendArray {
public:
  BackendArray() = default;
  BackendArray(Backend backend, std::size_t count) : backend_(backend) {
    if (backend == Backend::gpu)
      device_ = DeviceBuffer<T>(count);
    else
      host_.resize(count);
  }
  BackendArray(Backend backend, std::span<const T> values)
      : BackendArray(backend, values.size()) {
    if (backend == Backend::gpu)
      device_.upload(values);
    else
      std::copy(values.begin(), values.end(), host_.begin());
  }

  T* data() { return backend_ == Backend::gpu ? device_.data() : host_.data(); }
  const T* data() const { return backend_ == Backend::gpu ? device_.data() : host_.data(); }
  std::size_t size() const { return backend_ == Backend::gpu ? device_.size() : host_.size(); }
  std::vector<T> to_host() const {
    return backend_ == Backend::gpu ? device_.to_host() : host_;
  }
  void fill_bytes(unsigned char value) { // every byte `value`
    if (backend_ == Backend::gpu)
      device_.fill_bytes(value);
    else if (!host_.empty())
      std::memset(static_cast<void*>(host_.data()), value, host_.size() * sizeof(T));
  }
  void clear() { fill_bytes(0); }

private:
  Backend backend_ = Backend::cpu;
  std::vector<T> host_;
  DeviceBuffer<T> device_;
};

} // namespace rt
