// Chapter 02 tests on the CPU: the animation is deterministic and animated, and every missing
// piece of the display stack is a clear error rather than a crash.
#include <cstdlib>
#include <string>

#include "frames.h"
#include "gl_check.h"
#include "rt_catch.h"
#include "viewer.h"

using namespace rt;
using namespace rt::ch02;

TEST_CASE("CPU frames are the per-pixel pattern, and they move", "[ch02]") {
  const Extent extent{37, 23};
  const Image f0 = render_frame_image(Backend::cpu, extent, 0);
  const Image f1 = render_frame_image(Backend::cpu, extent, 1);
  for (int y = 0; y < extent.height; ++y)
    for (int x = 0; x < extent.width; ++x)
      REQUIRE(f0.at(x, y) == animated_pattern(x, y, extent.width, extent.height, 0));
  CHECK(count_differing_pixels(f0.pixels, f1.pixels) > f0.pixels.size() / 2);
  CHECK(count_differing_pixels(f1.pixels, render_frame_image(Backend::cpu, extent, 1).pixels) ==
        0);
}

TEST_CASE("a torn frame mixes two frames warp by warp, and its map marks the stale pixels",
          "[ch02]") {
  const Extent extent{64, 32}; // 4 x 2 blocks of 16 x 16, 8 warps each
  const Image before = render_frame_image(Backend::cpu, extent, 9);
  const Image after = render_frame_image(Backend::cpu, extent, 10);
  const Image picture = torn_frame(extent, 10);
  REQUIRE(picture.width == 2 * extent.width);
  REQUIRE(picture.height == extent.height);
  const Rgba8 white{255, 255, 255, 255};
  int stale_warps = 0;
  for (int y = 0; y < extent.height; y += 2)
    for (int x = 0; x < extent.width; x += 16) {
      // A warp is 16 x 2 pixels: all of them come from the same frame.
      const bool stale =
          picture.at(x, y) != after.at(x, y) || picture.at(x, y + 1) != after.at(x, y + 1);
      stale_warps += stale ? 1 : 0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 16; ++dx) {
          const Rgba8 shown = picture.at(x + dx, y + dy);
          REQUIRE(shown == (stale ? before : after).at(x + dx, y + dy));
          const bool marked = picture.at(extent.width + x + dx, y + dy) == white;
          REQUIRE(marked == (shown != after.at(x + dx, y + dy)));
        }
    }
  CHECK(stale_warps > 16 / 4); // of 64 warps, neither none nor all are stale
  CHECK(stale_warps < 64 - 16 / 4);
}

TEST_CASE("animated pattern values", "[ch02]") {
  // The centre pixel of a 4x4 image at frame 0: distance 0, no drift.
  const Rgba8 centre = animated_pattern(2, 2, 4, 4, 0);
  CHECK(int(centre.r) == 0);
  CHECK(int(centre.g) == (((2 ^ 2) * 2) & 0xff) / 2 + 64);
  CHECK(int(centre.a) == 255);
  // Negative frames and far pixels stay defined (unsigned wrap-around, no overflow).
  const Rgba8 far = animated_pattern(16383, 16383, 16384, 16384, -7);
  CHECK(int(far.a) == 255);
}

TEST_CASE("GL errors are named", "[ch02]") {
  CHECK(std::string(gl_error_name(GL_INVALID_OPERATION)) == "GL_INVALID_OPERATION");
  CHECK(std::string(gl_error_name(GL_OUT_OF_MEMORY)) == "GL_OUT_OF_MEMORY");
  CHECK(std::string(gl_error_name(0x1234)) == "unknown GL error");
}

TEST_CASE("no display is a DisplayError, not a crash", "[ch02]") {
  const char* display = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  const std::string saved_display = display ? display : "";
  const std::string saved_wayland = wayland ? wayland : "";
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  CHECK_FALSE(display_available());
  CHECK_THROWS_AS(Viewer(Extent{64, 32}, "test", false), DisplayError);
  setenv("DISPLAY", ":987654", 1); // a display that does not exist
  CHECK(display_available());
  CHECK_THROWS_AS(Viewer(Extent{64, 32}, "test", false), DisplayError);
  if (display)
    setenv("DISPLAY", saved_display.c_str(), 1);
  else
    unsetenv("DISPLAY");
  if (wayland) setenv("WAYLAND_DISPLAY", saved_wayland.c_str(), 1);
}
