// Chapter 07: the chapter's own report on one model: the median and SAH builds, brute force
// against both trees on the camera's rays (through the benchmark runner, with the float64
// reference on sampled rays), and chapter 06's shaded frame through the tree.
#pragma once

#include <string>
#include <vector>

#include "bvh.h"
#include "camera_spec.h"
#include "protocol.h"
#include "rt/backend.h"
#include "rt/report.h"
#include "shaded_scene.h"
#include "triangles.h"

namespace rt::ch07 {

struct ChapterReportOptions {
  std::string scene_path; // the OBJ file `scene` was loaded from
  Extent extent;
  BuildOptions build; // leaf size and bins of both trees
  ch04::TriangleVariant variant = ch04::TriangleVariant::watertight;
  bool smooth = true, shadows = true;
  long long reference_rays = k_protocol_reference_rays; // rays the float64 reference traces
  int frames = 0;                                       // timed runs; 0: the protocol's
};

// Adds the rows for each backend of `backends` (the GPU first, when there).
void report_chapter(const ChapterReportOptions& options, const std::vector<Backend>& backends,
                    const ch06::ShadedScene& scene, const ch03::Camera<float>& camera,
                    Report& report);

} // namespace rt::ch07
