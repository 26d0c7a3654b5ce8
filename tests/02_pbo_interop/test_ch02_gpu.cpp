// Chapter 02 tests on the GPU: GPU frames equal CPU frames, frame after frame.
#include "frames.h"
#include "gpu_guard.h"
#include "rt_catch.h"

using namespace rt;
using namespace rt::ch02;

TEST_CASE("GPU frames equal CPU frames", "[ch02][gpu]") {
  RT_REQUIRE_GPU();
  for (const Extent extent : {Extent{1, 1}, Extent{17, 13}, Extent{1280, 720}}) {
    for (int frame : {0, 1, 59, 1000}) {
      CAPTURE(extent.width, extent.height, frame);
      CHECK(count_differing_pixels(render_frame_image(Backend::gpu, extent, frame).pixels,
                                   render_frame_image(Backend::cpu, extent, frame).pixels) ==
            0);
    }
  }
}
