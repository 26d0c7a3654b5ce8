// Chapter 01 tests on the GPU: the hand-written kernel and the launch helper write every
// pixel exactly once, and the GPU images equal the CPU's.
#include "rt_catch.h"

#include "awkward_sizes.h"
#include "first_kernel.h"
#include "gpu_guard.h"
#include "rt/device_buffer.h"

using namespace rt;
using namespace rt::ch01;
using rt::testing::k_awkward_sizes;

TEST_CASE("GPU launch helper writes every pixel exactly once", "[ch01][gpu]") {
  RT_REQUIRE_GPU();
  for (const Extent extent : k_awkward_sizes) {
    for (const BlockShape block : {BlockShape{16, 16}, BlockShape{32, 8}, BlockShape{7, 3}}) {
      CAPTURE(extent.width, extent.height, block.x, block.y);
      const WriteAudit audit =
          audit_writes(count_helper_writes(Backend::gpu, extent, block), extent);
      CHECK(audit.never_written == 0);
      CHECK(audit.written_repeatedly == 0);
      CHECK(audit.past_the_end == 0);
    }
  }
}

TEST_CASE("hand-written kernel fills a poisoned buffer and nothing beyond it", "[ch01][gpu]") {
  RT_REQUIRE_GPU();
  for (const Extent extent : k_awkward_sizes) {
    CAPTURE(extent.width, extent.height);
    const BlockShape block{16, 16};
    const std::size_t n = static_cast<std::size_t>(extent.pixel_count());
    DeviceBuffer<Rgba8> d_image(n + 64); // 64 guard pixels after the image
    d_image.fill_bytes(0xCD);
    launch_first_kernel(d_image.data(), extent, block);
    const std::vector<Rgba8> out = d_image.to_host();
    const Image reference = render_image(Backend::cpu, extent, block);
    CHECK(count_differing_pixels(std::span(out.data(), n), reference.pixels) == 0);
    const Rgba8 poison{0xCD, 0xCD, 0xCD, 0xCD};
    for (std::size_t i = n; i < out.size(); ++i) REQUIRE(out[i] == poison);
  }
}

TEST_CASE("GPU and CPU images are identical", "[ch01][gpu]") {
  RT_REQUIRE_GPU();
  for (const Extent extent : k_awkward_sizes) {
    CAPTURE(extent.width, extent.height);
    const Image cpu = render_image(Backend::cpu, extent, {16, 16});
    CHECK(count_differing_pixels(render_image(Backend::gpu, extent, {16, 16}).pixels,
                                 cpu.pixels) == 0);
    CHECK(count_differing_pixels(render_first_frame_by_hand(extent, {16, 16}).image.pixels,
                                 cpu.pixels) == 0);
  }
}

TEST_CASE("flat offset check does the same damage on the GPU as the replayed grid",
          "[ch01][gpu]") {
  RT_REQUIRE_GPU();
  for (const Extent extent : {Extent{17, 2}, Extent{17, 13}, Extent{1920, 1080}}) {
    CAPTURE(extent.width, extent.height);
    const auto gpu = count_flat_offset_writes(Backend::gpu, extent, {16, 16});
    const auto cpu = count_flat_offset_writes(Backend::cpu, extent, {16, 16});
    CHECK(gpu == cpu);
  }
}
