// Chapter 09: from chapter 07's binary tree to a wide one. A wide node takes its children from
// the binary subtree below it; which ones is the whole question. The SAH collapse (Ylitie,
// Karras & Laine 2017) answers it by dynamic programming over the binary tree, the greedy one
// by opening the largest child until the node is full. Both end in the same layout: children in
// octant slots, interior children consecutive, each node's leaf triangles consecutive.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bvh.h"
#include "collapse_cost.h"
#include "mesh_gen.h"
#include "rt/launch.h"
#include "wide_bvh.h"

namespace rt::ch09 {

enum class Collapse { sah, greedy };

const char* to_string(Collapse collapse);

// A wide node with its children in their octant slots, before it is stored in a layout.
struct SlotNode {
  Aabb box;                        // the union of its children's boxes
  Aabb child_box[k_slots];         // the binary tree's box of each slot; empty slot: empty
  std::uint8_t meta[k_slots] = {}; // interior_meta / leaf_meta / 0 for an empty slot
  std::uint8_t imask = 0;          // bit s: slot s holds an interior child
  int child_base = 0;              // first interior child; the rest follow in slot order
  int triangle_base = 0;           // first triangle of its leaves, in slot order
};

// A collapsed tree: what pack_wide and compress store.
struct WideLayout {
  int width = k_slots;
  std::vector<SlotNode> nodes;      // node 0 is the root; none for a mesh with no triangles
  std::vector<TriangleF> triangles; // the leaves' references, in the order of the wide leaves
  std::vector<int> triangle_ids;    // the mesh's number of each
  WideStats stats;                  // bytes_per_triangle is the stored layout's: 0 here
  // The threads it was collapsed on, and the stored layouts are written on (0: the CPU
  // backend's). Which thread writes what changes nothing in what is written.
  int threads = 0;
};

// The binary tree each collapse starts from: chapter 07's build with `base`'s split method
// (sah, or sbvh with its split budget) and bins, with leaves of one triangle for the SAH
// collapse (which then chooses its leaves itself, as the paper does), of up to
// k_max_leaf_triangles for the greedy one (its leaves are kept).
ch07::BuildOptions binary_options(Collapse collapse, const ch07::BuildOptions& base);

// `binary` collapsed into nodes of at most `width` (2..8) children, on the binary build's
// threads (`binary.options.threads`; 0: the CPU backend's), the same layout bit for bit for
// any count. Throws InputError for a width out of range or a binary leaf of more than
// k_max_leaf_triangles triangles. A wide child's box is the binary tree's box of the entry it
// is made of, never recomputed from the triangles: from an sbvh tree that is the clipped box,
// smaller than its triangles' boxes. A wide leaf made of several binary leaves holds a
// triangle they share once.
WideLayout collapse(const ch07::Bvh& binary, int width, Collapse method);

// The whole build from a mesh: chapter 07's binary tree, then the collapse; build_ms counts
// both.
WideLayout build_wide_layout(const ch04::Mesh& mesh, int width, Collapse method,
                             const ch07::BuildOptions& base = {});

// The stored layouts, written on `layout.threads` threads. pack_wide<N> needs a layout of width
// <= N (N = 4 or 8; with PackedTriangles N = 4 only); compress one of width <= 8. Both throw
// InputError when a node's box cannot be stored (compress: wider than 255 * 2^120,
// about 3.4e38).
template <int N, class Triangles = AlignedTriangles>
WideTree<WideNode<N>, Triangles> pack_wide(const WideLayout& layout);
CompressedBvh compress(const WideLayout& layout);

// [listing:axis_grid]
// The grid of one node along one axis: origin = the node box's lo, step = 2^(exponent - 127),
// the smallest step from the box's extent up for which dequantise(255) >= the box's hi.
struct AxisGrid {
  float origin = 0.0f;
  std::uint8_t exponent = 0;
  float step() const { return grid_step(exponent); }
};
AxisGrid choose_grid(float lo, float hi);
// The tightest grid planes on the outer side of a child's exact box, found with the
// traversal's own dequantise: the largest q with dequantise(q) <= lo, the smallest with
// dequantise(q) >= hi. Both exist for grid.origin <= lo, hi <= the node's hi (q = 0, 255).
std::uint8_t quantise_lo(float lo, const AxisGrid& grid);
std::uint8_t quantise_hi(float hi, const AxisGrid& grid);
// [/listing:axis_grid]

// A child's box as the traversal sees it: the float box of a WideNode, the dequantised box of
// a CompressedNode (its planes computed as the traversal computes them).
template <int N> Aabb child_box_of(const WideNode<N>& node, int c);
Aabb child_box_of(const CompressedNode& node, int c);

// Everything the traversal relies on, checked against the mesh: every triangle in exactly one
// leaf, copied bit for bit with its id; every child box (dequantised, for the compressed node)
// containing the exact bounds of the triangles below it; child counts, meta bytes and imask
// consistent; interior children where child_base and imask say; every node reached once;
// depth within the traversal stack's bound. One line per problem; empty means valid.
// A tree collapsed from an sbvh tree (`binary.method`) is checked as chapter 07 checks one:
// every triangle in at least one leaf and never twice in one, at most (1 + split_budget) times
// the triangles in all, and each reference's triangle meeting the boxes on its way from the
// root (a leaf holds only the part of its triangle inside its box).
template <class Node, class Triangles>
std::vector<std::string> check_wide_tree(const WideTree<Node, Triangles>& tree,
                                         const ch04::Mesh& mesh,
                                         const ch07::BuildOptions& binary = {});

} // namespace rt::ch09
