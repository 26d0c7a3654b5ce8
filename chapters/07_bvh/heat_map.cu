// Chapter 07: the node-visit heat map. See heat_map.h.
#include "heat_map.h"

#include "rt/launch.h"
#include "traverse.h"

namespace rt::ch07 {

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
