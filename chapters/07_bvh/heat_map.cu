// Chapter 07: the node-visit heat map. See heat_map.h.
#include "heat_map.h"

#include "rt/launch.h"
#include "traverse.h"

namespace rt::ch07 {

RT_HD Rgba8 heat_colour(int nodes) {
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

void render_node_heat_map(Backend backend, const BvhView& bvh,
                          const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels) {
  for_each_pixel(backend, extent, [=] RT_HD(int x, int y) {
    Counters counters;
    trace_bvh<Query::closest, TriangleVariant::watertight>(bvh, camera.ray_through_pixel(x, y),
                                                           counters);
    pixels[y * extent.width + x] = heat_colour(counters.nodes);
  });
}

} // namespace rt::ch07
