// Chapter 13 tests: transforms and their checks, world boxes, and the two-level walk against
// the same scene flattened into one mesh.
#include <cmath>
#include <random>
#include <vector>

#include "rt_catch.h"

#include "instance.h"
#include "instance_scene.h"
#include "rt/error.h"
#include "two_level_scene.h"

using namespace rt;
using namespace rt::ch13;

TEST_CASE("an instance's two transforms undo each other", "[ch13][transform]") {
  const AffineD a = translation({3.0, -2.0, 1e4}) * rotation({1.0, 2.0, 3.0}, 0.7) *
                    scaling({2.0, 0.5, 1e-2});
  const AffineD identity = inverse(a) * a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) CHECK(std::abs(identity.m[r][c] - (r == c ? 1.0 : 0.0)) < 1e-9);
}
