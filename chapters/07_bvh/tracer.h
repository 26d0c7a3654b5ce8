// Chapter 07: a tracer is one way of answering "what does each of these rays hit?": a tree in
// some layout and the traversal that reads it. Every tree the course builds from here on (this
// chapter's, chapter 08's memory paths, later chapters' wide and GPU-built trees) registers as
// a tracer with the benchmark runner (runner.h), which measures them all on the same rays.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "bvh.h"
#include "bvh_trace.h"
#include "protocol.h"
#include "rt/backend.h"

namespace rt::ch07 {

// How a tracer's hits must relate to chapter 07's on the same rays.
enum class HitRule {
  identical,    // bit for bit: same t, same triangle (the same tree read another way)
  ties_allowed, // the same, except where two triangles lie at exactly the same distance: a tree
                // of another shape may test them in the other order and keep the other one
};

const char* to_string(HitRule rule);

// [listing:tracer]
struct Tracer {
  std::string name; // the last part of a report row: "<scene>, <ray type>, name"
  HitRule rule = HitRule::identical; // checked on every ray of every batch
  double bytes_per_triangle = 0;     // everything its traversal reads, over the triangle count
  bool camera_rays_only = false;     // makes its own primary rays (ignores the rays given)
  bool slow = false;                 // timed over a few runs only (brute force)
  // Rays and hits in device memory; empty where the tracer has no GPU path.
  std::function<void(Query, const RayF* d_rays, int count, MeshHit* d_hits)> trace_gpu;
  // Rays and hits in host memory, on CPU threads; empty where it has no CPU path.
  std::function<void(Query, std::span<const RayF> rays, std::span<MeshHit> hits)> trace_cpu;
  // Registers per thread of its GPU kernel; empty where that is not known.
  std::function<int(Query)> registers;
  // Nodes and triangles visited per ray (CPU, with counters); empty where not counted.
  std::function<TraversalWork(Query, std::span<const RayF> rays)> work;

  bool runs_on(Backend backend) const {
    return backend == Backend::gpu ? bool(trace_gpu) : bool(trace_cpu);
  }
};
// [/listing:tracer]

// What a tracer is made for: one scene, on one (resolved) backend. A maker uploads its tree
// once here and keeps it alive in the functions it returns.
struct TracerScene {
  std::string name;
  const ch04::Mesh& mesh;
  const Bvh& bvh;              // chapter 07's tree of the scene, built by the runner
  const PinholeCamera& camera; // the camera of the primary rays
  Backend backend;
  TriangleVariant variant = TriangleVariant::watertight;
};

using TracerMaker = std::function<std::vector<Tracer>(const TracerScene&)>;

// Chapter 07's own tracer: `scene.bvh` through trace_bvh, named after its build ("sah" or
// "median"). Later chapters compare with it.
std::vector<Tracer> chapter07_tracers(const TracerScene& scene);

// A tracer over another tree of chapter 07's layout (e.g. the median build beside the SAH one),
// named `name`; the tree is copied into the tracer.
Tracer bvh_tracer(std::string name, Bvh bvh, const TracerScene& scene);

// Brute force, chapter 04's closest_hit against every triangle: GPU only (too slow for a whole
// frame on CPU threads), closest hits, timed over a few runs.
Tracer brute_force_tracer(const TracerScene& scene);

} // namespace rt::ch07
