// Chapter 01: the per-pixel function. It colours each pixel by where it sits in the grid of
// thread blocks, so the picture shows how a launch carves an image into blocks.
#pragma once

#include "rt/hd.h"
#include "rt/image.h"
#include "rt/launch.h"

namespace rt::ch01 {

// [listing:block_pattern]
// Inside a block, red grows with threadIdx.x and green with threadIdx.y; neighbouring blocks
// alternate between a dark and a bright blue, like a checkerboard.
RT_HD inline Rgba8 block_pattern(int x, int y, BlockShape block) {
  const int block_x = x / block.x, thread_x = x % block.x; // blockIdx.x, threadIdx.x
  const int block_y = y / block.y, thread_y = y % block.y; // blockIdx.y, threadIdx.y
  const int red = 40 + 215 * thread_x / (block.x > 1 ? block.x - 1 : 1);
  const int green = 40 + 215 * thread_y / (block.y > 1 ? block.y - 1 : 1);
  const int blue = (block_x + block_y) % 2 == 0 ? 70 : 220;
  return {static_cast<unsigned char>(red), static_cast<unsigned char>(green),
          static_cast<unsigned char>(blue), 255};
}
// [/listing:block_pattern]

} // namespace rt::ch01
