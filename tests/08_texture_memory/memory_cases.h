// Chapter 08 test helpers shared by the CPU and GPU tests: chapter 07's hits, which every
// memory path must give bit for bit, and the first ray where two hit lists differ.
#pragma once

#include <vector>

#include "07_bvh/bvh_cases.h"
#include "bvh_trace.h"

namespace rt::testing {

// Chapter 07's CPU traversal with the watertight test: the reference every path must match.
inline std::vector<ch04::MeshHit> reference_hits(ch07::Query query, const ch07::Bvh& bvh,
                                                 const std::vector<RayF>& rays) {
  std::vector<ch04::MeshHit> hits(rays.size());
  ch07::trace_rays_cpu(query, ch04::TriangleVariant::watertight, bvh.view(), rays, hits);
  return hits;
}

// The first index where two hit lists differ in any bit (t and triangle), or -1; lists of
// different lengths differ at 0.
inline long long first_difference(const std::vector<ch04::MeshHit>& a,
                                  const std::vector<ch04::MeshHit>& b) {
  if (a.size() != b.size()) return 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_bits(a[i], b[i])) return static_cast<long long>(i);
  return -1;
}

} // namespace rt::testing
