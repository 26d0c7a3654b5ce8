// Chapter 01 tests on the CPU: every pixel written exactly once by the launch helper at
// awkward sizes, and the flat offset check's damage counted exactly.
#include "rt_catch.h"

#include "awkward_sizes.h"
#include "first_kernel.h"

using namespace rt;
using namespace rt::ch01;
using rt::testing::k_awkward_sizes;

TEST_CASE("launch helper writes every pixel exactly once on the CPU", "[ch01]") {
  for (const Extent extent : k_awkward_sizes) {
    for (const BlockShape block : {BlockShape{16, 16}, BlockShape{32, 8}, BlockShape{7, 3}}) {
      CAPTURE(extent.width, extent.height, block.x, block.y);
      const auto counts = count_helper_writes(Backend::cpu, extent, block);
      const WriteAudit audit = audit_writes(counts, extent);
      CHECK(audit.never_written == 0);
      CHECK(audit.written_repeatedly == 0);
      CHECK(audit.past_the_end == 0);
    }
  }
}

TEST_CASE("CPU render overwrites every poisoned pixel with the block pattern", "[ch01]") {
  const Extent extent{37, 19};
  const BlockShape block{16, 8};
  Image image(extent.width, extent.height);
  std::fill(image.pixels.begin(), image.pixels.end(), Rgba8{1, 2, 3, 4}); // poison
  render_block_pattern(Backend::cpu, image.pixels.data(), extent, block);
  for (int y = 0; y < extent.height; ++y)
    for (int x = 0; x < extent.width; ++x)
      REQUIRE(image.at(x, y) == block_pattern(x, y, block));
}

TEST_CASE("block pattern shows blocks: corners of a block and the checkerboard", "[ch01]") {
  const BlockShape block{16, 16};
  const Rgba8 first = block_pattern(0, 0, block);
  CHECK(int(first.r) == 40);
  CHECK(int(first.g) == 40);
  CHECK(int(first.b) == 70);
  const Rgba8 last_thread = block_pattern(15, 15, block);
  CHECK(int(last_thread.r) == 255);
  CHECK(int(last_thread.g) == 255);
  CHECK(int(block_pattern(16, 0, block).b) == 220);          // next block along the row
  CHECK(int(block_pattern(16, 16, block).b) == 70);          // diagonal neighbour
  CHECK(int(block_pattern(0, 0, BlockShape{1, 1}).r) == 40); // one-thread blocks are defined
}

TEST_CASE("flat offset check: one row, grid overhang", "[ch01]") {
  // 17 pixels, blocks of 16: the grid has 32 threads. Threads 0..16 write their pixel,
  // thread 17 has offset 17 == width*height and passes `offset > 17`: one write past the end.
  const Extent extent{17, 1};
  const WriteAudit audit =
      audit_writes(count_flat_offset_writes(Backend::cpu, extent, {16, 1}), extent);
  CHECK(audit.never_written == 0);
  CHECK(audit.written_repeatedly == 0);
  CHECK(audit.past_the_end == 1);
}

TEST_CASE("flat offset check: overhang threads wrap into the next row", "[ch01]") {
  // 17x2 pixels, blocks of 16x1: in row 0, threads x = 17..31 have offsets 17..31, which are
  // pixels 0..14 of row 1, which row 1's own threads write again. Row 1's thread x = 17 has
  // offset 34 == width*height: the write past the end.
  const Extent extent{17, 2};
  const auto counts = count_flat_offset_writes(Backend::cpu, extent, {16, 1});
  const WriteAudit audit = audit_writes(counts, extent);
  CHECK(audit.never_written == 0);
  CHECK(audit.written_repeatedly == 15);
  CHECK(audit.past_the_end == 1);
  for (int x = 0; x < 15; ++x) CHECK(counts[17 + x] == 2);
  CHECK(counts[17 + 15] == 1);
}

TEST_CASE("flat offset check is harmless only when blocks tile the image exactly", "[ch01]") {
  const Extent extent{64, 32};
  const WriteAudit audit =
      audit_writes(count_flat_offset_writes(Backend::cpu, extent, {16, 16}), extent);
  CHECK(audit.never_written == 0);
  CHECK(audit.written_repeatedly == 0);
  CHECK(audit.past_the_end == 0);
}

TEST_CASE("flat offset check corrupts the image that the 2D check gets right", "[ch01]") {
  const Extent extent{17, 13};
  const BlockShape block{16, 16};
  std::vector<Rgba8> flat(static_cast<std::size_t>(extent.pixel_count()) + 1,
                          Rgba8{1, 2, 3, 4});
  run_flat_offset_cpu(flat, extent, block);
  const Image good = render_image(Backend::cpu, extent, block);
  std::span<const Rgba8> flat_pixels(flat.data(), good.pixels.size());
  CHECK(count_differing_pixels(flat_pixels, good.pixels) > 0);
  CHECK_FALSE(flat.back() == Rgba8{1, 2, 3, 4}); // the guard past the end was written
}
