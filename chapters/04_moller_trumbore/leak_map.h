// Chapter 04: the picture of where the leak test's rays leak. Each closed mesh of the test at
// the origin is drawn from outside, and every ray that leaked marks the point it was aimed at:
// a point of an edge in red, a vertex in yellow.
#pragma once

#include "rt/image.h"
#include "rt/launch.h"
#include "triangles.h"

namespace rt::ch04 {

// The icosphere and the box of the leak test, side by side, each `panel` pixels, after
// `ray_count` rays each through `variant` on the CPU.
Image leak_map(TriangleVariant variant, int ray_count, Extent panel);

} // namespace rt::ch04
