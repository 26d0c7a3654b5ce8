// Chapter 09: the chapter's trees as tracers for chapter 07's benchmark runner, beside the
// binary tree they are measured against (chapter 08's kept path). A wide tree is another tree,
// not another reading of the same one, so its hits match chapter 07's up to exact ties.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "collapse.h"
#include "rt/report.h"
#include "runner.h"
#include "tracer.h"

namespace rt::ch09 {

using ch03::RayF;
using ch04::MeshHit;
using ch07::Query;

// [listing:chapter_tracers]
enum class ChapterTracer {
  binary,        // chapter 08's kept path: chapter 07's binary tree in 16-byte records
  wide4,         // SAH collapse to 4 children, float boxes
  wide8,         // SAH collapse to 8 children, float boxes
  cwbvh8,        // SAH collapse to 8 children, compressed 80-byte nodes (the paper's tree)
  cwbvh8_greedy, // greedy collapse to 8 children, compressed
  wide4_packed,  // wide4 with its triangles in 40-byte records instead of 48
  // The wide4 packed tree (the same one, built once) traversed other ways on the GPU:
  wide4_packed_shared_stack, // the stack's first entries in shared memory
  wide4_packed_persistent,   // persistent threads taking 32 rays a warp from a counter
  wide4_packed_sorted,       // the rays traced sorted by octant and origin, sort included
  // and an image's rays taken a tile of 8 x 4 pixels to a warp (RayOrder), by
  wide4_packed_tiles,            // the plain kernel
  wide4_packed_persistent_tiles, // persistent threads, a tile a warp from the counter
  // The CPU's own tree: the SAH collapse to 8 children, every child's address written out,
  // children visited nearest first (cpu_tree.h). CPU backend only.
  cpu8,
};
// [/listing:chapter_tracers]

inline constexpr ChapterTracer k_all_tracers[] = {ChapterTracer::binary,
                                                  ChapterTracer::wide4,
                                                  ChapterTracer::wide8,
                                                  ChapterTracer::cwbvh8,
                                                  ChapterTracer::cwbvh8_greedy,
                                                  ChapterTracer::wide4_packed,
                                                  ChapterTracer::wide4_packed_shared_stack,
                                                  ChapterTracer::wide4_packed_persistent,
                                                  ChapterTracer::wide4_packed_sorted,
                                                  ChapterTracer::wide4_packed_tiles,
                                                  ChapterTracer::wide4_packed_persistent_tiles,
                                                  ChapterTracer::cpu8};

// Whether the tracer is one of wide4 packed's traversal variants: its tree, traversed another
// way on the GPU, no tree of its own.
bool is_traversal_variant(ChapterTracer tracer);

// The name in report rows ("binary (ch07)", "cwbvh8 greedy", ...).
const char* to_string(ChapterTracer tracer);
// The tracer of a name on the command line ("binary", "cwbvh8_greedy", ...); throws UsageError
// naming the accepted names for an unknown one.
ChapterTracer parse_tracer(std::string_view name);

// A stored 4-wide tree with packed triangles (the chapter's `wide4 packed`) as a tracer named
// `name`, for trees collapsed from other binary trees.
ch07::Tracer wide4_tracer(std::string name, Wide4PackedBvh tree,
                          const ch07::TracerScene& scene);

// A wide tree's build, for a report row: called once per scene and wide tracer.
using BuildSink = std::function<void(const std::string& scene, const std::string& tracer,
                                     const WideStats& stats)>;

// The tracers of `tracers` for each scene. The wide trees are built from the scene's mesh
// with the bins of the runner's tree (binary_options), each binary tree and each wide tree
// once per scene (the variants of wide4 packed share its tree, and its build row).
ch07::TracerMaker chapter_tracers(std::vector<ChapterTracer> tracers, BuildSink on_build = {});

// Each wide tree's build as a report row, like chapter 07's build row: its time, nodes, depth,
// children per node, triangles per leaf, SAH cost and bytes per triangle.
ReportRow build_row(const std::string& scene, const std::string& tracer,
                    const WideStats& stats);

// A Markdown table of each tree's memory per scene: bytes per triangle, nodes and triangle
// records together, and the share of the binary tree's.
std::string memory_table(const std::vector<ch07::SceneResult>& results);

} // namespace rt::ch09
