// Chapter 07: the course's benchmark protocol (BENCHMARK.md beside the course) run on a list
// of scenes: primary, ambient occlusion and diffuse rays through the tree, kernel-only times,
// the build, the memory, and the end-to-end shaded frame, each row checked against brute force.
#pragma once

#include <string>
#include <vector>

#include "bvh.h"
#include "rt/backend.h"
#include "rt/launch.h"
#include "rt/report.h"
#include "triangles.h"

namespace rt::ch07 {

struct BenchmarkOptions {
  Extent extent{1920, 1080};
  Backend backend = Backend::gpu; // resolved
  ch04::TriangleVariant variant = ch04::TriangleVariant::watertight;
  BuildOptions build;
  int frames = 0;         // timed runs; 0: the protocol's (GPU 50 after 5, CPU 5 after 1)
  int check_rays = 4096;  // rays per ray type checked against brute force
  bool end_to_end = true; // also time the shaded frame
};

// One scene's figures, as the summary table prints them.
struct BenchmarkResult {
  std::string scene;
  long long triangles = 0;
  double mrays_primary = 0, mrays_ao = 0, mrays_diffuse = 0;
  double build_ms = 0, bytes_per_triangle = 0;
  double frame_ms = 0;      // end to end, shaded; 0 when not measured
  long long mismatches = 0; // sampled rays whose hit differs from brute force (not ties)
};

// The report row of a build: its time, Mtriangles/s, and the tree's statistics.
ReportRow build_row(const std::string& variant, const Bvh& bvh);

// A scene's name in tables: the file name without .obj and .gz ("models/conference.obj.gz"
// is "conference").
std::string scene_name(const std::string& path);

// The scenes of the benchmark set found in `folder` (stanford-bunny, armadillo-100k,
// stanford-dragon, conference, sponza-dabrovic, as .obj.gz); empty if none is there.
std::vector<std::string> benchmark_set(const std::string& folder);

// Runs the protocol on every scene, adding rows to `report`; returns the summary.
std::vector<BenchmarkResult> run_benchmark(const std::vector<std::string>& scenes,
                                           const BenchmarkOptions& options, Report& report);

// The summary as a Markdown table (what the book prints), with the industry's anchors for
// the GPU it ran on when BENCHMARK.md has them.
std::string summary_table(const std::vector<BenchmarkResult>& results,
                          const std::string& device);

} // namespace rt::ch07
