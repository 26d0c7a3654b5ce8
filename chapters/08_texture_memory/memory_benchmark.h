// Chapter 08: every memory path measured on a scene. The protocol's rays (chapter 07): primary,
// ambient occlusion and diffuse; each path timed kernel-only on the GPU (median of CPU runs on
// the CPU) and its hits compared bit for bit with chapter 07's, which are traced first on the
// same backend. Optionally also the error of a sample against the float64 reference.
#pragma once

#include <string>
#include <vector>

#include "bvh.h"
#include "memory_paths.h"
#include "protocol.h"
#include "rt/backend.h"
#include "rt/launch.h"
#include "rt/report.h"

namespace rt::ch08 {

struct MeasureOptions {
  Extent extent{1920, 1080};
  std::vector<Backend> backends{Backend::gpu}; // resolved; each path where it runs
  std::vector<MemoryPath> paths{std::begin(k_all_paths), std::end(k_all_paths)};
  std::vector<ch07::RayType> ray_types{ch07::RayType::primary, ch07::RayType::ao,
                                       ch07::RayType::diffuse};
  ch07::BuildOptions build;
  int frames = 0;               // timed runs; 0: the protocol's (GPU 50 after 5, CPU 5 after 1)
  long long reference_rays = 0; // rays per type checked against float64 (0: none)
  bool constants = true;        // GPU: the primary rays made in the kernel, both ways
};

// One path's figure for one ray type on one backend.
struct PathFigure {
  MemoryPath path;
  ch07::RayType type;
  Backend backend;
  double mrays = 0;
  long long differing = 0; // hits not bit-identical to chapter 07's
};

struct SceneFigures {
  std::string scene;
  long long triangles = 0;
  std::vector<PathFigure> figures;
  double camera_mrays[2] = {0, 0}; // GPU primary rays made in the kernel: parameters, constant
  long long differing = 0;         // over every row of the scene
};

// Measures one scene (an OBJ file), adding a row per path, ray type and backend to `report`.
SceneFigures measure_scene(const std::string& scene_path, const MeasureOptions& options,
                           Report& report);

// The Markdown tables the book prints: Mrays/s per scene and path, one table per ray type,
// for the GPU rows.
std::string path_tables(const std::vector<SceneFigures>& scenes, const MeasureOptions& options,
                        const std::string& device);

} // namespace rt::ch08
