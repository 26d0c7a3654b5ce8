// Chapter 09: an order for a batch of rays in which neighbours tend to visit the same nodes.
// Each ray gets a 30-bit key, its direction's octant above a Morton code of its origin; the
// rays are traced in the order of their keys (the GPU sorts them with CUB, the CPU with
// std::sort). One RT_HD key function, so both backends compute the same keys.
#pragma once

#include <span>
#include <vector>

#include "bvh.h"
#include "wide_traverse.h"

namespace rt::ch09 {

using ch03::RayF;

// The grid the origins are quantised to: 512 cells per axis over the scene's box. The
// protocol's rays start on the scene's surfaces or at the camera; a camera outside the box
// clamps to its nearest cells, which costs nothing, since every camera ray then shares it.
struct RaySortFrame {
  Vec3f lo{0.0f, 0.0f, 0.0f};
  Vec3f cells_per_unit{0.0f, 0.0f, 0.0f}; // 0 on an axis of no extent
};

inline constexpr int k_sort_cell_bits = 9;                       // per axis
inline constexpr int k_sort_key_bits = 3 + 3 * k_sort_cell_bits; // octant, Morton code
inline constexpr float k_sort_last_cell = (1 << k_sort_cell_bits) - 1;

RaySortFrame make_ray_sort_frame(const ch07::Aabb& scene_bounds);

// The cell of one coordinate: NaN and below the box go to cell 0, beyond it to the last.
RT_HD inline unsigned sort_cell(float x, float lo, float cells_per_unit) {
  const float cell = (x - lo) * cells_per_unit;
  return cell > 0.0f ? (cell < k_sort_last_cell ? unsigned(cell) : unsigned(k_sort_last_cell))
                     : 0u;
}

// The 9 bits of `x` spread to every third bit (bit k to bit 3k).
RT_HD inline unsigned spread_every_third_bit(unsigned x) {
  x &= 0x1ffu;
  x = (x | (x << 16)) & 0x030000ffu;
  x = (x | (x << 8)) & 0x0300f00fu;
  x = (x | (x << 4)) & 0x030c30c3u;
  x = (x | (x << 2)) & 0x09249249u;
  return x;
}

// [listing:ray_sort_key]
// A ray's key: its octant in bits 27..29 (the sign bits of its direction, as the traversal's
// make_wide_ray reads them), then the Morton code of its origin's cell. Rays of one octant
// visit a node's children in the same order, and rays from nearby origins start in the same
// subtrees. The origin alone, not origin and direction: within an octant, a diffuse ray's
// direction says little about which leaves it reaches, and every bit spent on it is taken from
// the origin's grid. Primary rays all share the camera's cell, so their keys are their octants
// and the sort keeps them in pixel order within each (it is stable), which is coherent already.
RT_HD inline unsigned ray_sort_key(const RayF& ray, const RaySortFrame& frame) {
  const unsigned octant = 7u - make_wide_ray(ray).octant_inverse;
  const unsigned x = sort_cell(ray.origin.x, frame.lo.x, frame.cells_per_unit.x);
  const unsigned y = sort_cell(ray.origin.y, frame.lo.y, frame.cells_per_unit.y);
  const unsigned z = sort_cell(ray.origin.z, frame.lo.z, frame.cells_per_unit.z);
  return octant << (3 * k_sort_cell_bits) | spread_every_third_bit(x) |
         spread_every_third_bit(y) << 1 | spread_every_third_bit(z) << 2;
}
// [/listing:ray_sort_key]

// The rays' indices in the order they are traced: by key, equal keys by index (the order of
// a stable radix sort, CUB's on the GPU).
std::vector<int> sorted_ray_order(std::span<const RayF> rays, const RaySortFrame& frame);

} // namespace rt::ch09
