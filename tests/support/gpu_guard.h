// [gpu] tests call RT_REQUIRE_GPU() first. Without a usable CUDA device the test fails with the
// reason: such tests are excluded by label on machines without a GPU, never passed silently.
#pragma once

#include <string>

#include "rt_catch.h"

namespace rt::testing {
// Empty when a GPU is usable, else the reason it is not.
std::string gpu_unavailable_reason();
} // namespace rt::testing

#define RT_REQUIRE_GPU()                                                                       \
  do {                                                                                         \
    const std::string rt_reason = ::rt::testing::gpu_unavailable_reason();                     \
    if (!rt_reason.empty()) FAIL("this [gpu] test needs a usable CUDA device: " << rt_reason); \
  } while (false)
