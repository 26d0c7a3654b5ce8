// Chapter 01: the first kernel launch, the bounds-check bug it is easy to write, and the
// launch helper every later chapter uses. Host-callable entry points; kernels in the .cu.
#pragma once

#include <span>
#include <vector>

#include "block_pattern.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "rt/launch.h"

namespace rt::ch01 {

// blockIdx and threadIdx of one thread, so a CPU loop can replay a grid thread by thread.
struct ThreadIndex {
  int block_x, block_y;   // blockIdx.x, blockIdx.y
  int thread_x, thread_y; // threadIdx.x, threadIdx.y
};

// [listing:flat_offset_thread]
// What one thread does under a flat bounds check on the offset into the image. Two bugs:
// `>` admits offset == width*height, one element past the end; and a thread in the grid's
// overhang (x >= width) passes the test and wraps into the start of the next row.
template <class Sink>
RT_HD void flat_offset_thread(ThreadIndex t, BlockShape block, Extent image, Sink write) {
  const int x = t.block_x * block.x + t.thread_x;
  const int y = t.block_y * block.y + t.thread_y;
  const int offset = x + y * image.width;
  if (offset > image.width * image.height) return; // should be: x < width && y < height
  write(offset, block_pattern(x, y, block));
}
// [/listing:flat_offset_thread]

// Replays a grid on the CPU: every block, every thread, in order.
template <class ThreadFn> void emulate_grid(Extent image, BlockShape block, ThreadFn fn) {
  const int grid_x = blocks_to_cover(image.width, block.x);
  const int grid_y = blocks_to_cover(image.height, block.y);
  for (int by = 0; by < grid_y; ++by)
    for (int bx = 0; bx < grid_x; ++bx)
      for (int ty = 0; ty < block.y; ++ty)
        for (int tx = 0; tx < block.x; ++tx) fn(ThreadIndex{bx, by, tx, ty});
}

// 1. The hand-written kernel with the right check; d_image holds width*height pixels.
void launch_first_kernel(Rgba8* d_image, Extent image, BlockShape block);

// 2. The flat offset check. The buffers hold width*height + 1 elements: the last one is a
// guard that catches the write past the end instead of corrupting memory.
void launch_flat_offset_kernel(Rgba8* d_image_with_guard, Extent image, BlockShape block);
void run_flat_offset_cpu(std::span<Rgba8> image_with_guard, Extent image, BlockShape block);
// Write counts per element (last = guard) under the flat check, on either backend.
std::vector<unsigned> count_flat_offset_writes(Backend backend, Extent image, BlockShape block);

// 3. The launch helper: block_pattern over the image on the resolved backend. `pixels` is
// device memory for Backend::gpu and host memory for Backend::cpu.
void render_block_pattern(Backend backend, Rgba8* pixels, Extent image, BlockShape block);
// Write counts per pixel plus one guard element under the launch helper.
std::vector<unsigned> count_helper_writes(Backend backend, Extent image, BlockShape block);

// What a set of write counts says about a launch.
struct WriteAudit {
  long long never_written = 0;      // pixels no thread wrote
  long long written_repeatedly = 0; // pixels two or more threads wrote (a race on the GPU)
  long long past_the_end = 0;       // writes that landed beyond the last pixel
};
WriteAudit audit_writes(std::span<const unsigned> counts_with_guard, Extent image);

// Whole images, for the demo and the tests.
Image render_image(Backend backend, Extent image, BlockShape block);

// 4. The hand-written kernel's frame with every CUDA call written out: allocation, the copies
// both ways, the launch and its timing with events. The rest of the course lets common/ do
// these steps (DeviceBuffer, CudaEvent, time_gpu).
struct FirstFrame {
  Image image;     // what the kernel wrote over a poisoned buffer
  float kernel_ms; // the first launch, measured by events: no warm-up before it
};
FirstFrame render_first_frame_by_hand(Extent image, BlockShape block);

} // namespace rt::ch01
