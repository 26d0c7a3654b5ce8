// Chapter 10: the chapter's builders side by side. Each builds a tree in chapter 07's layout
// for a scene; chapter 07's runner then measures each tree twice, as it is (chapter 07's
// binary traversal) and collapsed to four children by chapter 09 (the course's fastest
// traversal on an H200), so a build's time can be weighed against the rays it speeds up.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "bvh.h"
#include "mesh_gen.h"
#include "rt/backend.h"
#include "rt/report.h"
#include "runner.h"
#include "tracer.h"
#include "wide_collapse.h"

namespace rt::ch10 {

// [listing:builders]
enum class Builder {
  cpu_sah, // chapter 07's binned SAH build, leaves of one, on one CPU core: the quality mark
  lbvh,    // Karras's LBVH from 30-bit Morton codes
  lbvh63,  // the same from 63-bit codes
  ploc,    // PLOC: clusters merged with their nearest neighbours, from 30-bit Morton order
  hploc,   // H-PLOC: PLOC inside the 30-bit LBVH's subtrees, in one walk up its hierarchy
  hploc_treelets, // H-PLOC's tree, then rounds of treelet restructuring (treelets.h)
};
// [/listing:builders]

inline constexpr Builder k_all_builders[] = {Builder::cpu_sah, Builder::lbvh,
                                             Builder::lbvh63,  Builder::ploc,
                                             Builder::hploc,   Builder::hploc_treelets};

// The name in report rows ("CPU SAH (ch07)", "LBVH", ...).
const char* to_string(Builder builder);
// The builder of a name on the command line (cpu_sah, lbvh, lbvh63, ploc, hploc,
// hploc_treelets); throws
// UsageError naming them for an unknown one.
Builder parse_builder(std::string_view name);

// A tree and how it was built.
struct BuiltTree {
  ch07::Bvh bvh;
  Backend backend = Backend::cpu; // where it was built: chapter 07's build is always the CPU
  std::string note;               // what the build had to do differently, if anything
  double collapse_ms = 0.0; // the parallel collapse to 4-wide (wide_collapse.h), on `backend`
  double collapse_depth_ms = 0.0; // the same by the depth rule, which looks at no cost
};

// Builds `mesh`'s tree with `builder`, the parallel ones on `backend` (resolved). The build
// time is bvh.stats.build_ms.
BuiltTree build_tree(Builder builder, Backend backend, const ch04::Mesh& mesh);

// The report row of a build: time, Mtriangles/s, nodes, depth, SAH cost, and the note.
ReportRow build_row(const std::string& scene, Builder builder, const BuiltTree& tree);

// Called once per scene and builder with the tree built.
using BuildSink =
    std::function<void(const std::string& scene, Builder builder, const BuiltTree& tree)>;

// For each scene, the tree of each of `builders` as three tracers: "<builder>" (chapter 07's
// traversal), "<builder> 4-wide" (chapter 09's SAH collapse to four children, on the CPU) and
// "<builder> 4-wide (parallel collapse)" (this chapter's collapse by `rule`, on the scene's
// backend; by the sah rule chapter 09's tree, made in parallel; the depth rule's tracer ends
// in ", depth rule)"). BuiltTree::collapse_ms is the sah rule's time, collapse_depth_ms the
// depth rule's, both measured whichever is traced. Their hits match chapter 07's up to exact
// ties.
ch07::TracerMaker builder_tracers(std::vector<Builder> builders, BuildSink on_build = {},
                                  CollapseRule rule = CollapseRule::sah);

// The builds as a Markdown table: builder, where, ms, the parallel collapse's ms (sah rule,
// depth rule), SAH cost, depth, nodes.
std::string build_table(const std::vector<std::pair<Builder, BuiltTree>>& builds);

} // namespace rt::ch10
