// The launch helper (end of chapter 01): runs one RT_HD per-pixel function `fn(x, y)` over a
// width x height image, either as a CUDA kernel on a 2D grid of 2D blocks or on all CPU cores.
// Every later chapter renders through it; for_each_index, its 1-D form, runs the passes of
// chapters 10 and 11 (one function per item). GPU launches need a .cu translation unit.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "rt/backend.h"
#include "rt/cpu_progress.h"
#include "rt/error.h"
#include "rt/hd.h"

#if RT_DEVICE_CODE_POSSIBLE
#include <cuda_runtime.h>

#include "rt/cuda_check.h"
#endif

namespace rt {

struct Extent {
  int width = 0;  // pixels per row
  int height = 0; // rows
  long long pixel_count() const { return static_cast<long long>(width) * height; }
};

struct BlockShape {
  int x = 16; // threads per block along a row
  int y = 16; // threads per block down a column
};

// Blocks needed to cover `n` items with blocks of `block` items: the grid is rounded up, so
// the last block may hang over the edge of the image.
constexpr int blocks_to_cover(int n, int block) { return (n + block - 1) / block; }

// [listing:pixel_tiles]
// Pixels numbered in tiles of 8 x 4, a warp's worth each, for kernels that run a thread per
// number: a warp's 32 rays then leave from a small square of the image rather than from a
// strip of one row, and stay closer together in the scene (chapter 11's paths, chapter 13's
// shaded frame). Numbers past the image's edge, in the tiles that hang over it, are no pixel.
struct PixelTiles {
  static constexpr int k_width = 8, k_height = 4; // one warp
  int width = 0, height = 0, tiles_x = 0, tiles_y = 0;
  RT_HD PixelTiles(int w, int h)
      : width(w), height(h), tiles_x((w + k_width - 1) / k_width),
        tiles_y((h + k_height - 1) / k_height) {}
  // The numbers to cover: every tile's 32.
  RT_HD long long count() const {
    return static_cast<long long>(tiles_x) * tiles_y * (k_width * k_height);
  }
  // Number `index`'s pixel; false past the image's edge.
  RT_HD bool pixel(unsigned index, int& x, int& y) const {
    const unsigned tile = index / unsigned(k_width * k_height),
                   within = index % unsigned(k_width * k_height);
    x = int((tile % unsigned(tiles_x)) * k_width + within % k_width);
    y = int((tile / unsigned(tiles_x)) * k_height + within / k_width);
    return x < width && y < height;
  }
};
// [/listing:pixel_tiles]

#if RT_DEVICE_CODE_POSSIBLE
// [listing:launch_kernel]
template <class PixelFn>
__global__ void for_each_pixel_kernel(int width, int height, PixelFn fn) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x;
  const int y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x < width && y < height) fn(x, y); // the rounded-up grid hangs over both edges
}

template <class PixelFn>
void for_each_pixel_gpu(Extent extent, PixelFn fn, BlockShape block = {},
                        cudaStream_t stream = 0) {
  if (extent.width <= 0 || extent.height <= 0) return;
  const dim3 threads(block.x, block.y);
  const dim3 grid(blocks_to_cover(extent.width, block.x),
                  blocks_to_cover(extent.height, block.y));
  for_each_pixel_kernel<<<grid, threads, 0, stream>>>(extent.width, extent.height, fn);
  RT_CUDA_CHECK_LAUNCH("for_each_pixel_kernel");
}
// [/listing:launch_kernel]
#endif

// [listing:launch_cpu]
template <class PixelFn> void for_each_pixel_cpu(Extent extent, PixelFn fn) {
  if (extent.width <= 0 || extent.height <= 0) return;
  std::atomic<int> next_row{0}; // rows are handed out one at a time: cheap load balancing
  std::atomic<int> rows_done{0};
  auto work = [&](auto after_row) {
    for (int y = next_row++; y < extent.height; y = next_row++) {
      for (int x = 0; x < extent.width; ++x) fn(x, y);
      after_row(++rows_done);
    }
  };
  const int thread_count = std::min(cpu_thread_count(), extent.height);
  // Long work says how far it has come (rt/cpu_progress.h). Made before the threads, it is
  // destroyed after they are joined, when every row is done.
  CpuProgress progress(extent.height, "rows");
  std::vector<std::jthread> threads;
  for (int t = 1; t < thread_count; ++t) threads.emplace_back(work, [](int) {});
  work([&](int done) { progress.update(done); }); // the calling thread works, and reports
}
// [/listing:launch_cpu]

// Runs fn on the resolved backend (Backend::gpu or Backend::cpu).
template <class PixelFn>
void for_each_pixel(Backend backend, Extent extent, PixelFn fn, BlockShape block = {}) {
  if (backend == Backend::cpu) return for_each_pixel_cpu(extent, fn);
  if (backend != Backend::gpu) throw Error("for_each_pixel: resolve the backend first");
#if RT_DEVICE_CODE_POSSIBLE
  for_each_pixel_gpu(extent, fn, block);
#else
  (void)block;
  throw Error("for_each_pixel: GPU launch from a file not compiled by nvcc");
#endif
}

// fn(i) for every i in 0 .. count-1 on `threads` CPU threads (the calling one among them).
// Items are handed out in chunks of up to 256 from a shared counter: cheap load balancing when
// some cost far more than others. A small batch (chapter 07's float64 reference: a thousand
// rays, each costing milliseconds on a large model) gets smaller chunks, at least 64 per
// thread, so that the work spreads evenly and its progress line, counting `unit`, moves.
// An exception leaving fn on any thread stops the handing out, and once every thread is done
// the one of the lowest i is thrown again here: the one a loop on one thread would have met
// first (every chunk not yet handed out lies beyond every chunk that was).
template <class Fn>
void for_each_index_cpu(std::size_t count, Fn fn, int threads = cpu_thread_count(),
                        const char* unit = "rays") {
  const std::size_t chunk = std::clamp<std::size_t>(
      count / (64 * static_cast<std::size_t>(std::max(threads, 1))), 1, 256);
  std::atomic<std::size_t> next{0}, done{0};
  std::mutex failure_mutex;
  std::size_t failed_at = count;
  std::exception_ptr failure;
  auto worker = [&](auto after_chunk) {
    std::size_t i = 0;
    try {
      for (std::size_t start = next.fetch_add(chunk); start < count;
           start = next.fetch_add(chunk)) {
        const std::size_t end = std::min(count, start + chunk);
        for (i = start; i < end; ++i) fn(i);
        after_chunk(done += end - start);
      }
    } catch (...) {
      next = count; // hand out nothing more
      const std::lock_guard lock(failure_mutex);
      if (i < failed_at) {
        failed_at = i;
        failure = std::current_exception();
      }
    }
  };
  threads = std::max(1, std::min<int>(threads, int(count / chunk) + 1));
  {
    // A long batch says how far it has come, as for_each_pixel_cpu does.
    CpuProgress progress(static_cast<long long>(count), unit);
    std::vector<std::jthread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker, [](std::size_t) {});
    worker(
        [&](std::size_t items_done) { progress.update(static_cast<long long>(items_done)); });
  } // the pool joins here
  if (failure) std::rethrow_exception(failure);
}

#if RT_DEVICE_CODE_POSSIBLE
inline constexpr int k_index_block = 256; // threads per block of for_each_index's kernel

template <class Fn> __global__ void for_each_index_kernel(int count, Fn fn) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < count) fn(i);
}

// fn(i) for i = this thread's number, then that plus the launch's thread count, and so on.
template <class Fn> __global__ void for_each_index_strided_kernel(int count, Fn fn) {
  const int stride = gridDim.x * blockDim.x;
  for (int i = blockIdx.x * blockDim.x + threadIdx.x; i < count; i += stride) fn(i);
}

// for_each_index's GPU launch on a stream of its own, to run beside the default stream's work
// (chapter 11's wavefront finishes a sample's last paths while the next sample starts), by at
// most `threads` threads (whole blocks), each taking every threads-th index: a launch that
// leaves most of the GPU to the work beside it. 0: a thread per index.
template <class Fn>
void for_each_index_on(cudaStream_t stream, int count, Fn fn, int threads = 0) {
  if (count <= 0) return;
  const int blocks =
      blocks_to_cover(threads > 0 ? std::min(count, threads) : count, k_index_block);
  for_each_index_strided_kernel<<<blocks, k_index_block, 0, stream>>>(count, fn);
  RT_CUDA_CHECK_LAUNCH("for_each_index_strided_kernel");
}
#endif

// [listing:for_each_index]
// fn(i) for every i in 0 .. count-1: one GPU thread each, or chunks of them on CPU threads.
template <class Fn> void for_each_index(Backend backend, int count, Fn fn) {
  if (count <= 0) return;
  if (backend == Backend::cpu) {
    for_each_index_cpu(static_cast<std::size_t>(count),
                       [&](std::size_t i) { fn(static_cast<int>(i)); });
    return;
  }
  if (backend != Backend::gpu) throw Error("for_each_index: resolve the backend first");
#if RT_DEVICE_CODE_POSSIBLE
  for_each_index_kernel<<<blocks_to_cover(count, k_index_block), k_index_block>>>(count, fn);
  RT_CUDA_CHECK_LAUNCH("for_each_index_kernel");
#else
  throw Error("for_each_index: GPU launch from a file not compiled by nvcc");
#endif
}
// [/listing:for_each_index]

} // namespace rt
