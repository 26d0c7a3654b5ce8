// Chapter 09: the order of a batch of rays on the CPU. See ray_sort.h.
#include "ray_sort.h"

#include <algorithm>
#include <utility>

namespace rt::ch09 {

RaySortFrame make_ray_sort_frame(const ch07::Aabb& scene_bounds) {
  if (scene_bounds.empty()) return {};
  const auto cells = [](float lo, float hi) {
    return hi > lo ? float(1 << k_sort_cell_bits) / (hi - lo) : 0.0f;
  };
  const Vec3f lo = scene_bounds.lo, hi = scene_bounds.hi;
  return {lo, {cells(lo.x, hi.x), cells(lo.y, hi.y), cells(lo.z, hi.z)}};
}

std::vector<int> sorted_ray_order(std::span<const RayF> rays, const RaySortFrame& frame) {
  std::vector<std::pair<unsigned, int>> keyed(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i)
    keyed[i] = {ray_sort_key(rays[i], frame), static_cast<int>(i)};
  std::sort(keyed.begin(), keyed.end()); // by key, then by index
  std::vector<int> order(rays.size());
  for (std::size_t j = 0; j < keyed.size(); ++j) order[j] = keyed[j].second;
  return order;
}

} // namespace rt::ch09
