// Chapter 02: an animated per-pixel pattern, so that frames per second mean something. Integer
// arithmetic only: the GPU and the CPU must draw bit-identical frames for the report to hold
// every display path to "0 pixels differ".
#pragma once

#include <cstdint>

#include "rt/hd.h"
#include "rt/image.h"

namespace rt::ch02 {

// [listing:animated_pattern]
// Rings spreading out from the centre over a diagonal interference pattern that drifts.
RT_HD inline Rgba8 animated_pattern(int x, int y, int width, int height, int frame) {
  const int dx = x - width / 2, dy = y - height / 2;
  const std::uint32_t d2 = std::uint32_t(dx * dx + dy * dy);
  const std::uint32_t ring = (d2 >> 7) - std::uint32_t(frame) * 3u; // moves outwards
  const std::uint32_t drift = std::uint32_t((x + frame) ^ (y - frame / 2));
  const std::uint32_t r = ring & 0xffu;
  const std::uint32_t g = (drift * 2u) & 0xffu;
  const std::uint32_t b = (ring ^ drift) & 0xffu;
  return {std::uint8_t(r), std::uint8_t(g / 2u + 64u), std::uint8_t(b), 255};
}
// [/listing:animated_pattern]

} // namespace rt::ch02
