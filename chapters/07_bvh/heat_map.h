// Chapter 07: where a tree makes a ray work. Each pixel's camera ray goes through the tree
// with the traversal's counters, and the pixel shows how many interior nodes it visited: the
// picture of a good tree is dark, of a poor one (overlapping boxes) bright.
#pragma once

#include "bvh.h"
#include "camera_spec.h"
#include "rt/backend.h"
#include "rt/image.h"

namespace rt::ch07 {

inline constexpr int k_heat_map_max_nodes = 48; // white: this many node visits or more

// The colour of `nodes` visits: black for none, through purple, red and yellow, to white at
// k_heat_map_max_nodes; linear in the count between those stops. Inline, so that a later
// chapter's kernels colour their own counts the same way.
RT_HD inline Rgba8 heat_colour(int nodes) {
  constexpr int k_stops = 5;
  constexpr float k_colour[k_stops][3] = {{0.0f, 0.0f, 0.0f},
                                          {0.35f, 0.1f, 0.55f},
                                          {0.85f, 0.2f, 0.2f},
                                          {1.0f, 0.8f, 0.1f},
                                          {1.0f, 1.0f, 1.0f}};
  const float x =
      static_cast<float>(nodes < k_heat_map_max_nodes ? nodes : k_heat_map_max_nodes) /
      k_heat_map_max_nodes * (k_stops - 1);
  const int low = x < k_stops - 1 ? static_cast<int>(x) : k_stops - 2;
  const float f = x - static_cast<float>(low);
  const auto channel = [&](int c) {
    const float value = k_colour[low][c] + f * (k_colour[low + 1][c] - k_colour[low][c]);
    return static_cast<std::uint8_t>(value * 255.0f + 0.5f);
  };
  return {channel(0), channel(1), channel(2), 255};
}

// Nodes visited by each pixel's camera ray (closest hit, watertight test) as heat colours.
// The tree and pixels are in device memory on the GPU backend, host memory on the CPU.
void render_node_heat_map(Backend backend, const BvhView& bvh,
                          const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels);

} // namespace rt::ch07
