// Chapter 07, optional: a CPU tracer of the course measured against Embree 3 (Intel's CPU ray
// tracer) on the same threads and the very same rays, with the hits of the two compared ray by
// ray. Chapter 07's program compares its binary tree; later chapters' programs compare theirs.
// Built only where Embree is installed (the library rt_ch07_embree); nothing else needs it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "tracer.h"

namespace rt::ch07 {

// "Ours" on one scene: the tracer measured against Embree, and how its tree was built, for the
// line under the table.
struct OursOnScene {
  Tracer tracer;       // traced through trace_cpu
  double build_ms = 0; // its whole build from the mesh
  std::string build;   // how it was built: "binned SAH, 2 threads"
  std::string cost;    // its tree's cost model: "SAH cost 55.1"
};

// What a program compares with Embree.
struct EmbreeCompareProgram {
  std::string name;                 // the program: "ch07_embree_compare"
  std::string title;                // the first line of --help
  std::string report_title;         // the JSON report's title (Embree's version appended)
  std::vector<std::string> tracers; // the names --tracer takes; the first is the default
  // Makes the tracer named `tracer` (one of `tracers`) for one scene, on the CPU backend.
  // `scene.bvh` is chapter 07's SAH tree of the scene, which the comparison builds anyway (it
  // frames the camera): a tracer may read it, or build a tree of its own.
  std::function<OursOnScene(const std::string& tracer, const TracerScene& scene)> make_ours;
};

// The whole program: its options (--width, --height, --runs, --tracer, --threads, --robust,
// --split, --split-budget, --json, scenes), then for each scene both builds, the protocol's
// primary, ao and diffuse rays through both, timed turn about, one Markdown table each. Returns
// the exit code; an error is one line (run_main).
int run_embree_compare(int argc, char** argv, const EmbreeCompareProgram& program);

} // namespace rt::ch07
