// RAII owners for GPU resources (chapter 01): a device allocation and a CUDA event. Each frees
// its resource in its destructor, so nothing leaks when an exception unwinds the stack.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <cuda_runtime_api.h>

#include "rt/cuda_check.h"

namespace rt {

template <class T> class DeviceBuffer {
public:
  DeviceBuffer() = default;
  explicit DeviceBuffer(std::size_t count) : count_(count) {
    if (count == 0) return;
    const std::size_t bytes = count * sizeof(T);
    if (bytes / sizeof(T) != count) throw InputError("device buffer size overflows");
    const std::string what = "cudaMalloc of " + std::to_string(bytes) + " bytes";
    cuda_check(cudaMalloc(reinterpret_cast<void**>(&data_), bytes), what.c_str(), __FILE__,
               __LINE__);
  }
  explicit DeviceBuffer(std::span<const T> host) : DeviceBuffer(host.size()) { upload(host); }
  ~DeviceBuffer() { reset(); }

  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& other) noexcept { swap(other); }
  DeviceBuffer& operator=(DeviceBuffer&& other) noexcept {
    DeviceBuffer(std::move(other)).swap(*this);
    return *this;
  }

  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return count_; }
  std::size_t bytes() const { return count_ * sizeof(T); }

  void upload(std::span<const T> host) {
    if (host.size() != count_) throw Error("DeviceBuffer::upload: size mismatch");
    if (count_ == 0) return;
    RT_CUDA_CHECK(cudaMemcpy(data_, host.data(), bytes(), cudaMemcpyHostToDevice));
  }
  void download(std::span<T> host) const {
    if (host.size() != count_) throw Error("DeviceBuffer::download: size mismatch");
    if (count_ == 0) return;
    RT_CUDA_CHECK(cudaMemcpy(host.data(), data_, bytes(), cudaMemcpyDeviceToHost));
  }
  std::vector<T> to_host() const {
    std::vector<T> host(count_);
    download(host);
    return host;
  }
  // Sets every byte to `value` (used to poison buffers before a kernel writes them).
  void fill_bytes(unsigned char value) {
    if (count_ == 0) return;
    RT_CUDA_CHECK(cudaMemset(data_, value, bytes()));
  }

private:
  void reset() {
    if (data_ != nullptr) cudaFree(data_); // never throws from a destructor
    data_ = nullptr;
    count_ = 0;
  }
  void swap(DeviceBuffer& other) noexcept {
    std::swap(data_, other.data_);
    std::swap(count_, other.count_);
  }

  T* data_ = nullptr;     // device pointer, owned
  std::size_t count_ = 0; // number of elements
};

class CudaEvent {
public:
  // cudaEventDisableTiming for an event that only orders streams: it costs less to record.
  explicit CudaEvent(unsigned flags = cudaEventDefault) {
    RT_CUDA_CHECK(cudaEventCreateWithFlags(&event_, flags));
  }
  ~CudaEvent() {
    if (event_ != nullptr) cudaEventDestroy(event_);
  }
  CudaEvent(const CudaEvent&) = delete;
  CudaEvent& operator=(const CudaEvent&) = delete;

  void record(cudaStream_t stream = nullptr) { RT_CUDA_CHECK(cudaEventRecord(event_, stream)); }
  void synchronize() { RT_CUDA_CHECK(cudaEventSynchronize(event_)); }
  // Milliseconds from `start` to this event; both must have completed.
  float milliseconds_since(const CudaEvent& start) const {
    float ms = 0.0f;
    RT_CUDA_CHECK(cudaEventElapsedTime(&ms, start.event_, event_));
    return ms;
  }
  cudaEvent_t get() const { return event_; }

private:
  cudaEvent_t event_ = nullptr;
};

// A CUDA stream that does not wait for the legacy default stream, nor it for this one: work
// here runs beside the default stream's launches, ordered with them only by events.
class CudaStream {
public:
  CudaStream() { RT_CUDA_CHECK(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking)); }
  ~CudaStream() {
    if (stream_ != nullptr) cudaStreamDestroy(stream_);
  }
  CudaStream(const CudaStream&) = delete;
  CudaStream& operator=(const CudaStream&) = delete;

  // Work queued on `stream` after this call waits until `event` (as last recorded) is done.
  static void wait(cudaStream_t stream, const CudaEvent& event) {
    RT_CUDA_CHECK(cudaStreamWaitEvent(stream, event.get(), 0));
  }
  cudaStream_t get() const { return stream_; }

private:
  cudaStream_t stream_ = nullptr;
};

} // namespace rt
