// Chapter 07: the float64 reference of a batch of rays, on a sample: every triangle, in double,
// on the float rays (chapter 06's closest_surface). What a report's error column is measured
// against.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "mesh_gen.h"
#include "ray.h"
#include "rt/report.h"
#include "shade.h"
#include "triangles.h"

namespace rt::ch07 {

struct Reference {
  std::vector<std::size_t> index; // which rays of the batch
  std::vector<ch06::SurfaceHit<double>> hits;
};

// About `count` evenly spaced rays of `rays`, traced in double on CPU cores.
Reference trace_reference(const ch04::Mesh& mesh, std::span<const ch03::RayF> rays,
                          long long count);

// Hits of the whole batch against the reference's few: triangles that differ, and the worst
// relative error of t where the triangle is the same. Adds both as metrics of `row`.
std::string error_against(const Reference& ref, std::span<const ch04::MeshHit> hits,
                          ReportRow& row);

} // namespace rt::ch07
