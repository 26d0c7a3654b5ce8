// Chapter 01: the first kernel launch. See first_kernel.h for the map of this file.
#include "first_kernel.h"

#include "rt/atomic.h"
#include "rt/backend_image.h"
#include "rt/cuda_check.h"
#include "rt/device_buffer.h"

namespace rt::ch01 {

// [listing:first_kernel]
__global__ void first_kernel(Rgba8* image, int width, int height) {
  // Each thread finds its pixel from where its block sits in the grid and where it sits in
  // its block.
  const int x = blockIdx.x * blockDim.x + threadIdx.x;
  const int y = blockIdx.y * blockDim.y + threadIdx.y;
  // The grid is rounded up to whole blocks, so it can hang over the right and bottom edges:
  // threads out there must do nothing. Test x and y, not the flat offset.
  if (x >= width || y >= height) return;
  image[y * width + x] = block_pattern(x, y, BlockShape{int(blockDim.x), int(blockDim.y)});
}

void launch_first_kernel(Rgba8* d_image, Extent image, BlockShape block) {
  const dim3 threads(block.x, block.y);                    // threads per block
  const dim3 grid(blocks_to_cover(image.width, block.x),   // blocks per row
                  blocks_to_cover(image.height, block.y)); // blocks per column
  first_kernel<<<grid, threads>>>(d_image, image.width, image.height);
  RT_CUDA_CHECK_LAUNCH("first_kernel");
}
// [/listing:first_kernel]

template <class Sink>
__global__ void flat_offset_kernel(Extent image, BlockShape block, Sink write) {
  const ThreadIndex t{int(blockIdx.x), int(blockIdx.y), int(threadIdx.x), int(threadIdx.y)};
  flat_offset_thread(t, block, image, write);
}

template <class Sink>
static void launch_flat_offset(Extent image, BlockShape block, Sink write) {
  const dim3 threads(block.x, block.y);
  const dim3 grid(blocks_to_cover(image.width, block.x),
                  blocks_to_cover(image.height, block.y));
  flat_offset_kernel<<<grid, threads>>>(image, block, write);
  RT_CUDA_CHECK_LAUNCH("flat_offset_kernel");
}

void launch_flat_offset_kernel(Rgba8* d_image_with_guard, Extent image, BlockShape block) {
  launch_flat_offset(image, block,
                     [=] __device__(int offset, Rgba8 c) { d_image_with_guard[offset] = c; });
}

void run_flat_offset_cpu(std::span<Rgba8> image_with_guard, Extent image, BlockShape block) {
  Rgba8* out = image_with_guard.data();
  emulate_grid(image, block, [&](ThreadIndex t) {
    flat_offset_thread(t, block, image, [&](int offset, Rgba8 c) { out[offset] = c; });
  });
}

static std::size_t with_guard(Extent image) {
  return static_cast<std::size_t>(image.pixel_count()) + 1;
}

std::vector<unsigned> count_flat_offset_writes(Backend backend, Extent image,
                                               BlockShape block) {
  if (backend == Backend::cpu) {
    std::vector<unsigned> counts(with_guard(image), 0u);
    unsigned* c = counts.data();
    emulate_grid(image, block, [&](ThreadIndex t) {
      flat_offset_thread(t, block, image, [&](int offset, Rgba8) { ++c[offset]; });
    });
    return counts;
  }
  DeviceBuffer<unsigned> d_counts(with_guard(image));
  d_counts.fill_bytes(0);
  unsigned* c = d_counts.data();
  launch_flat_offset(image, block,
                     [=] __device__(int offset, Rgba8) { atomicAdd(c + offset, 1u); });
  return d_counts.to_host();
}

// [listing:render_with_helper]
void render_block_pattern(Backend backend, Rgba8* pixels, Extent image, BlockShape block) {
  const int width = image.width;
  for_each_pixel(
      backend, image,
      [=] RT_HD(int x, int y) { pixels[y * width + x] = block_pattern(x, y, block); }, block);
}
// [/listing:render_with_helper]

static void count_helper_writes_into(unsigned* counts, Backend backend, Extent image,
                                     BlockShape block) {
  const int width = image.width;
  for_each_pixel(
      backend, image, [=] RT_HD(int x, int y) { atomic_increment(counts + y * width + x); },
      block);
}

std::vector<unsigned> count_helper_writes(Backend backend, Extent image, BlockShape block) {
  if (backend == Backend::cpu) {
    std::vector<unsigned> counts(with_guard(image), 0u);
    count_helper_writes_into(counts.data(), backend, image, block);
    return counts;
  }
  DeviceBuffer<unsigned> d_counts(with_guard(image));
  d_counts.fill_bytes(0);
  count_helper_writes_into(d_counts.data(), backend, image, block);
  return d_counts.to_host();
}

WriteAudit audit_writes(std::span<const unsigned> counts_with_guard, Extent image) {
  WriteAudit audit;
  const std::size_t pixels = static_cast<std::size_t>(image.pixel_count());
  for (std::size_t i = 0; i < pixels; ++i) {
    audit.never_written += counts_with_guard[i] == 0 ? 1 : 0;
    audit.written_repeatedly += counts_with_guard[i] > 1 ? 1 : 0;
  }
  for (std::size_t i = pixels; i < counts_with_guard.size(); ++i)
    audit.past_the_end += counts_with_guard[i];
  return audit;
}

Image render_image(Backend backend, Extent extent, BlockShape block) {
  return render_into_image(backend, extent, [&](Rgba8* pixels) {
    render_block_pattern(backend, pixels, extent, block);
  });
}

// [listing:first_frame_by_hand]
FirstFrame render_first_frame_by_hand(Extent image, BlockShape block) {
  const std::size_t bytes = static_cast<std::size_t>(image.pixel_count()) * sizeof(Rgba8);
  FirstFrame frame{Image(image.width, image.height), 0.0f};
  for (Rgba8& p : frame.image.pixels) p = {0xCD, 0xCD, 0xCD, 0xCD}; // poison: shows gaps
  Rgba8* d_image = nullptr;                    // device memory: the GPU's own DRAM
  cudaEvent_t start = nullptr, stop = nullptr; // time stamps the GPU itself takes
  cudaError_t status = cudaMalloc(&d_image, bytes);
  if (status == cudaSuccess) // host -> device, over the bus
    status = cudaMemcpy(d_image, frame.image.pixels.data(), bytes, cudaMemcpyHostToDevice);
  if (status == cudaSuccess) status = cudaEventCreate(&start);
  if (status == cudaSuccess) status = cudaEventCreate(&stop);
  if (status == cudaSuccess) {
    cudaEventRecord(start); // queued on the default stream...
    first_kernel<<<dim3(blocks_to_cover(image.width, block.x),
                        blocks_to_cover(image.height, block.y)),
                   dim3(block.x, block.y)>>>(d_image, image.width, image.height);
    cudaEventRecord(stop);       // ...after the kernel: all three calls return at once
    status = cudaGetLastError(); // a launch that could not start says so here
  }
  if (status == cudaSuccess) status = cudaEventSynchronize(stop); // the CPU waits here
  if (status == cudaSuccess) status = cudaEventElapsedTime(&frame.kernel_ms, start, stop);
  if (status == cudaSuccess) // device -> host: the kernel's pixels
    status = cudaMemcpy(frame.image.pixels.data(), d_image, bytes, cudaMemcpyDeviceToHost);
  if (stop != nullptr) cudaEventDestroy(stop); // released on every path, failed or not
  if (start != nullptr) cudaEventDestroy(start);
  cudaFree(d_image);
  RT_CUDA_CHECK(status);
  return frame;
}
// [/listing:first_frame_by_hand]

} // namespace rt::ch01
