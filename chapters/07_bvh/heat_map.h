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
// k_heat_map_max_nodes; linear in the count between those stops.
RT_HD Rgba8 heat_colour(int nodes);

// Nodes visited by each pixel's camera ray (closest hit, watertight test) as heat colours.
// The tree and pixels are in device memory on the GPU backend, host memory on the CPU.
void render_node_heat_map(Backend backend, const BvhView& bvh,
                          const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels);

} // namespace rt::ch07
