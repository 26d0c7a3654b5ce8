// Chapter 10: Morton codes, the one idea that turns a tree build into a sort. A triangle's
// centroid is quantised to an integer grid over the scene's bounds, and the bits of its three
// grid coordinates are interleaved: triangles close in space get codes close in value, so
// sorting by code lays the triangles out along a space-filling curve (the Z-order curve).
#pragma once

#include <cstdint>

#include "bvh.h"
#include "rt/hd.h"
#include "rt/vec.h"

namespace rt::ch10 {

using ch07::Aabb;

// The two code widths: 10 bits per axis in a 32-bit word, 21 bits per axis in a 64-bit one.
enum class CodeWidth { bits30, bits63 };

const char* to_string(CodeWidth width);

template <class Code> struct CodeTraits;
template <> struct CodeTraits<std::uint32_t> { static constexpr int bits_per_axis = 10; };
template <> struct CodeTraits<std::uint64_t> { static constexpr int bits_per_axis = 21; };

// [listing:morton_spread]
// The 10 low bits of x spread out with two zero bits between them: bit k moves to bit 3k.
// Each step moves the upper half of the bits still together by a power of two and masks off
// what the shift dragged along (the masks keep one group of bits every 3 * 2^k).
RT_HD inline std::uint32_t spread_bits_10(std::uint32_t x) {
  x &= 0x3ffu;
  x = (x | (x << 16)) & 0x030000ffu;
  x = (x | (x << 8)) & 0x0300f00fu;
  x = (x | (x << 4)) & 0x030c30c3u;
  x = (x | (x << 2)) & 0x09249249u;
  return x;
}

// The same for the 21 low bits of x in a 64-bit word: bit k moves to bit 3k.
RT_HD inline std::uint64_t spread_bits_21(std::uint64_t x) {
  x &= 0x1fffffull;
  x = (x | (x << 32)) & 0x1f00000000ffffull;
  x = (x | (x << 16)) & 0x1f0000ff0000ffull;
  x = (x | (x << 8)) & 0x100f00f00f00f00full;
  x = (x | (x << 4)) & 0x10c30c30c30c30c3ull;
  x = (x | (x << 2)) & 0x1249249249249249ull;
  return x;
}

// x's bits go to 3k + 2, y's to 3k + 1, z's to 3k: the order is x y z x y z ... from the top.
RT_HD inline std::uint32_t morton30(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  return (spread_bits_10(x) << 2) | (spread_bits_10(y) << 1) | spread_bits_10(z);
}
RT_HD inline std::uint64_t morton63(std::uint64_t x, std::uint64_t y, std::uint64_t z) {
  return (spread_bits_21(x) << 2) | (spread_bits_21(y) << 1) | spread_bits_21(z);
}
// [/listing:morton_spread]

// [listing:quantise]
// A coordinate's cell on a grid of 2^bits cells per axis over [lo, hi]. Computed from halves
// of every value, so that no difference overflows even for a scene spanning the whole float
// range; a flat axis (lo == hi) puts everything in cell 0. The arithmetic is a fixed sequence
// of float operations (the file is compiled without fused multiply-adds), so the CPU and the
// GPU put every centroid in the same cell.
RT_HD inline std::uint32_t grid_cell(float c, float lo, float hi, int bits) {
  const float half_extent = 0.5f * hi - 0.5f * lo;
  if (!(half_extent > 0.0f)) return 0;
  const float cells = static_cast<float>(1u << bits);
  const float q = (0.5f * c - 0.5f * lo) / half_extent * cells;
  if (!(q > 0.0f)) return 0;
  return q >= cells - 1.0f ? (1u << bits) - 1u : static_cast<std::uint32_t>(q);
}

// The centroid of a triangle's box, halves of each end as chapter 07's build computes it.
RT_HD inline Vec3f box_centroid(const Aabb& box) { return 0.5f * box.lo + 0.5f * box.hi; }

// The code of a triangle's box within the scene's centroid bounds.
template <class Code> RT_HD inline Code morton_code(const Aabb& box, const Aabb& centroids) {
  constexpr int bits = CodeTraits<Code>::bits_per_axis;
  const Vec3f c = box_centroid(box);
  const std::uint32_t x = grid_cell(c.x, centroids.lo.x, centroids.hi.x, bits);
  const std::uint32_t y = grid_cell(c.y, centroids.lo.y, centroids.hi.y, bits);
  const std::uint32_t z = grid_cell(c.z, centroids.lo.z, centroids.hi.z, bits);
  if constexpr (bits == 10) {
    return morton30(x, y, z);
  } else {
    return morton63(x, y, z);
  }
}
// [/listing:quantise]

} // namespace rt::ch10
