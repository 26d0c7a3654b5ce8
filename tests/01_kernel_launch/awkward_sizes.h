// Image sizes that catch bounds bugs: a single pixel, primes, one more than a block, full HD.
#pragma once

#include "rt/launch.h"

namespace rt::testing {

inline constexpr Extent k_awkward_sizes[] = {{1, 1},   {17, 13}, {16, 16}, {17, 16},
                                             {16, 17}, {33, 1},  {1, 257}, {1920, 1080}};

} // namespace rt::testing
