// Chapter 10: chapter 07's binary tree collapsed to chapter 09's fastest node (Wide4PackedBvh)
// in parallel passes, on the GPU or on CPU threads, so that a tree built on the GPU is traced
// the fast way without a trip to the host. Both backends give the same wide tree bit for bit.
#pragma once

#include "collapse_cost.h"
#include "rt/backend.h"
#include "rt/backend_array.h"
#include "tree_arrays.h"
#include "wide_bvh.h"

namespace rt::ch10 {

inline constexpr int k_wide_leaf_triangles = ch09::k_max_leaf_triangles;

// Which binary nodes become what.
// - sah: chapter 09's SAH collapse, its choices made in parallel: every node's costs from the
//   bottom up (as the refit climbs), then each node finds from the root down whether it is a
//   wide node. The same wide tree as chapter 09's (node for node; numbered otherwise).
// - depth: decided by each node alone, looking at no cost: a binary node covering at most
//   three triangles is a leaf of its wide parent; an interior one covering more, at even
//   depth, is a wide node (the root always is). A wide node's children are its two binary
//   children, each one covering more than three triangles replaced by its own two.
enum class CollapseRule { sah, depth };

const char* to_string(CollapseRule rule);
CollapseRule parse_collapse_rule(const std::string& name); // "sah" or "depth"; else UsageError

// [listing:wide_order_record]
// A wide node's children in slot order, as the collapse's second pass works them out from the
// binary nodes (two levels of them, the triangle ranges, the octant slots) and keeps them for
// the third and fourth, which would otherwise work them out again. Position p holds a child
// where from[p] >= 0.
struct alignas(16) WideOrder {
  int from[4];   // its box is child from & 1 of binary node from >> 1
  int target[4]; // an interior child's binary node; a leaf's first triangle
  int count[4];  // a leaf's triangles; 0 for an interior child
  int slot[4];   // its octant slot
};
// [/listing:wide_order_record]

// What the sah rule's bottom-up pass leaves at a node for its parent: its spread (the least
// cost of j = 2..4 children shared between its two sides: spread[j - 2]) and the left side's
// share of each (bits 2(j - 2) and up of k), and its triangles, first .. end - 1.
struct alignas(8) CostRecord {
  double spread[3];
  int first, end, k;
};

// The collapse's arrays, made once for trees of `triangle_count` triangles; run() collapses a
// tree (every frame's, in an animation) with the passes alone: on the GPU nothing waits.
class WideCollapse {
public:
  // `leaf_size`: the most triangles a wide leaf takes (1 to 3); binary subtrees of more are
  // opened. Chapter 13 collapses a tree over instance boxes with leaves of one, each child box
  // then the box of one instance.
  WideCollapse(Backend backend, int triangle_count, int leaf_size = ch09::k_max_leaf_triangles,
               CollapseRule rule = CollapseRule::sah);
  // `binary`: this chapter's tree of triangle_count triangles, leaves of one to three.
  void run(const TreeArrays& binary);
  // The same from a tree's arrays (backend pointers): node_count nodes, their parent links, the
  // triangles in leaf order, or null where there are none (a tree over boxes: its records then
  // hold the ids alone, PackedTriangles::id), and the ids.
  void run(const ch07::BvhNode* nodes, const int* parents, int node_count,
           const ch04::TriangleF* triangles, const int* ids);
  // What the traversal reads (backend pointers). node_count is the arrays' capacity: the
  // traversal only asks whether it is zero.
  ch09::Wide4PackedBvh::View view() const;
  // The last tree run() made, in host memory, its stats filled (build_ms left at 0).
  ch09::Wide4PackedBvh to_host() const;

private:
  Backend backend_;
  int triangle_count_, leaf_size_, capacity_;
  CollapseRule rule_;
  // range_first_ and range_end_: the depth rule's (the sah rule keeps ranges in CostRecord).
  BackendArray<int> range_first_, range_end_, is_wide_, interior_counts_, leaf_counts_,
      interior_offsets_, triangle_offsets_, wide_index_, wide_total_;
  BackendArray<WideOrder> orders_; // 64 bytes per binary node, set for the wide ones
  BackendArray<ch09::WideNode<4>> nodes_;
  BackendArray<float2> records_;
  BackendArray<int> sources_; // per record: its triangle's place in the binary leaf order
  BackendArray<unsigned char> scratch_;
  // The sah rule's, per binary node: what its parent reads (CostRecord), its choices
  // (packed), its arrival counter.
  BackendArray<CostRecord> records_sah_;
  BackendArray<unsigned> choices_, arrivals_;
};

// `binary` (it passes chapter 07's checker; leaves of at most three triangles) collapsed on the
// backend; stats.build_ms is the collapse's time, measured as a build's (rt::BackendStopwatch).
// Throws InputError for a larger leaf.
ch09::Wide4PackedBvh collapse_to_wide4(Backend backend, const ch07::Bvh& binary,
                                       CollapseRule rule = CollapseRule::sah);

// A wide tree's report figures, computed from the tree itself as chapter 09's collapse
// computes them (its cost model, over the root's area); build_ms is kept.
void fill_wide_stats(ch09::Wide4PackedBvh& tree);

} // namespace rt::ch10
