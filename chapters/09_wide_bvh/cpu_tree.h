// Chapter 09: the CPU's own wide tree. The GPU's nodes are shaped for a warp: a node packs its
// children's addresses into a base and meta bytes, and the stack holds bit masks, because
// registers and memory traffic are what a GPU thread runs short of. A CPU core has a large
// cache, deep out-of-order execution and branch prediction; what it runs short of is work it
// can skip. So the CPU's node spends bytes to save instructions (every child's address written
// out), and its traversal keeps each child's entry distance on the stack, so that a child
// farther than the nearest hit found since it was pushed is dropped without being read.
// Both trees come from the same collapse (collapse.h), so they hold the same boxes and the
// same leaves, and give the same hits up to exact ties.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "bvh_trace.h"
#include "collapse.h"
#include "traverse.h"
#include "wide_bvh.h"
#include "wide_traverse.h"

namespace rt::ch09 {

using ch03::RayF;
using ch04::MeshHit;
using ch07::Query;

// [listing:cpu_node]
// One node of up to 8 children, 256 bytes, aligned to a 64-byte cache line:
//
//   byte   0 .. 191  lo_x[8] lo_y[8] lo_z[8] hi_x[8] hi_y[8] hi_z[8]  (float32, as WideNode<8>)
//   byte 192 .. 223  child[8]: an interior child's node number (>= 0), or for a leaf the
//                    flag bit 31 with the leaf's triangles as bits of the node's triangle
//                    block (bit k: triangle triangle_base + k; 24 bits, as in the hit mask)
//   byte 224 .. 227  triangle_base: the first triangle of the node's leaves
//   then padding
//
// An empty child has an empty box (lo = +inf, hi = -inf), which no ray enters, and a leaf
// with no triangles. The children are in the collapse's slot order; the traversal orders them
// by distance, not by slot, so the slots no longer matter.
struct alignas(64) CpuNode {
  static constexpr int k_width = k_slots;
  float lo_x[k_slots], lo_y[k_slots], lo_z[k_slots];
  float hi_x[k_slots], hi_y[k_slots], hi_z[k_slots];
  int child[k_slots];
  int triangle_base;
};
static_assert(sizeof(CpuNode) == 256 && offsetof(CpuNode, child) == 192);
static_assert(offsetof(CpuNode, lo_x) == 0 && offsetof(CpuNode, hi_z) == 5 * 32,
              "the planes lie as WideNode<8>'s, so enter_eight reads both");

inline constexpr unsigned k_cpu_leaf_flag = 0x80000000u;
inline constexpr unsigned k_cpu_leaf_bits = 0x00ffffffu;
constexpr int cpu_leaf_child(unsigned triangle_bits) {
  return static_cast<int>(k_cpu_leaf_flag | (triangle_bits & k_cpu_leaf_bits));
}
constexpr bool is_cpu_leaf(int child) { return child < 0; }
constexpr unsigned cpu_leaf_triangles(int child) {
  return static_cast<unsigned>(child) & k_cpu_leaf_bits;
}
// [/listing:cpu_node]

// [listing:cpu_triangles]
// The triangles as the CPU tests them, eight at a time: in blocks of eight, each block the
// nine coordinates (v0.x v0.y v0.z v1.x ... v2.z) of its eight triangles, eight floats each,
// 288 consecutive bytes. A node's triangles start a block (its triangle_base is a multiple of
// 8; the last block of a node is padded), so the eight triangles a test reads lie in one
// block: five cache lines side by side, where nine columns the length of the mesh would cost
// nine lines far apart.
inline constexpr int k_block_triangles = 8;
inline constexpr int k_block_floats = 9 * k_block_triangles;

// What the CPU traversal reads: the nodes, the triangle blocks (`columns`) and the mesh's
// number of each triangle. Host memory only.
struct CpuTreeView {
  const CpuNode* nodes = nullptr;
  const float* columns = nullptr; // the blocks
  const int* ids = nullptr;       // the mesh's triangle number of each slot; -1 for padding
  int node_count = 0;             // 0 only for a mesh with no triangles

  const CpuNode& node(int i) const { return nodes[i]; }
  // Coordinate c of triangle k.
  float coordinate(int k, int c) const {
    return columns[std::size_t(k / k_block_triangles) * k_block_floats + c * k_block_triangles +
                   k % k_block_triangles];
  }
  TriangleF triangle(int k) const {
    const auto at = [&](int c) { return coordinate(k, c); };
    return {{at(0), at(1), at(2)}, {at(3), at(4), at(5)}, {at(6), at(7), at(8)}};
  }
  int triangle_id(int k) const { return ids[k]; }
};
// [/listing:cpu_triangles]

// Triangles k .. k + 7 (k a multiple of 8) for the eight-at-once test: one block.
inline EightColumns eight_columns(const CpuTreeView& tree, int k) {
  return {tree.columns + std::size_t(k / k_block_triangles) * k_block_floats,
          k_block_triangles};
}

// A CPU tree, owned.
struct CpuTree {
  std::vector<CpuNode> nodes; // node 0 is the root
  std::vector<float> columns; // the triangle blocks
  std::vector<int> ids;       // per triangle slot, padding included
  WideStats stats; // the collapse's, with the stored layout's time and bytes per triangle

  CpuTreeView view() const {
    return {nodes.data(), columns.data(), ids.data(), static_cast<int>(nodes.size())};
  }
};

// A collapsed tree (width <= 8) stored as the CPU reads it. Throws InputError for a wider one.
CpuTree pack_cpu(const WideLayout& layout);

// Rays in host memory through the tree on the CPU backend's threads: closest or any hit.
void trace_cpu_tree(Query query, const CpuTreeView& tree, std::span<const RayF> rays,
                    std::span<MeshHit> hits);

// Nodes read and triangles tested per ray, and the deepest stack (with counters).
ch07::TraversalWork measure_cpu_tree_work(Query query, const CpuTreeView& tree,
                                          std::span<const RayF> rays);

} // namespace rt::ch09
