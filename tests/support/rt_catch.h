// One include for every test file: Catch2 v2 (Debian 12, Ubuntu 22.04) or v3 (Ubuntu 24.04),
// with the few names that differ between them made the same.
#pragma once

// RT_CATCH_V3 comes from CMake (tests/support/CMakeLists.txt), which knows the version found.
#if RT_CATCH_V3
#include <catch2/catch_all.hpp>
using Catch::Approx;
#else
#include <catch2/catch.hpp>
#endif

#include <string>

namespace rt::testing {
#if RT_CATCH_V3
inline auto contains(const std::string& s) { return Catch::Matchers::ContainsSubstring(s); }
inline auto starts_with(const std::string& s) { return Catch::Matchers::StartsWith(s); }
#else
inline auto contains(const std::string& s) { return Catch::Contains(s); }
inline auto starts_with(const std::string& s) { return Catch::StartsWith(s); }
#endif
} // namespace rt::testing
