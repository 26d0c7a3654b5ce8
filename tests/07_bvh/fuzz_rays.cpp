// Chapter 07: the libFuzzer target for the ray-file reader (built and run by tools/fuzz.sh,
// beside chapter 05's OBJ target). Any bytes may be refused, with rt::InputError naming the
// file in one line, but never crash, touch memory they do not own, do undefined arithmetic,
// throw anything else, or come back as a ray the reader promises never to return.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>

#include "ray_io.h"
#include "rt/error.h"
#include "supported_range.h"

namespace {

[[noreturn]] void bug(const std::string& what) {
  std::fprintf(stderr, "fuzz_rays: %s\n", what.c_str());
  std::abort(); // libFuzzer saves the input that got here as a crash
}

bool finite(rt::Vec3f v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// What read_ray_file promises of every ray it returns (ray_io.h).
bool traceable(const rt::ch07::RayF& ray) {
  const float largest = rt::max_component(rt::elementwise_abs(ray.direction));
  return finite(ray.origin) && finite(ray.direction) && std::isfinite(ray.tmin) &&
         !std::isnan(ray.tmax) &&
         rt::max_component(rt::elementwise_abs(ray.origin)) <= rt::ch03::k_max_coordinate &&
         largest >= rt::ch07::k_min_direction && largest <= rt::ch07::k_max_direction;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr long long k_max_rays = 4096; // a small limit keeps each run fast
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    const auto rays = rt::ch07::parse_ray_bytes(bytes, "fuzz.rays", k_max_rays);
    if (rays.size() * sizeof(rt::ch07::RayF) != size) bug("rays returned for a ragged size");
    if (static_cast<long long>(rays.size()) > k_max_rays) bug("more rays than the limit");
    for (const auto& ray : rays)
      if (!traceable(ray)) bug("a ray outside what the reader promises was returned");
  } catch (const rt::InputError& error) {
    const std::string message = error.what();
    if (message.rfind("fuzz.rays: ", 0) != 0) bug("error without the file name: " + message);
    if (message.find('\n') != std::string::npos) bug("error of several lines: " + message);
  }
  return 0;
}
