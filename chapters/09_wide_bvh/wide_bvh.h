// Chapter 09: wide trees as they lie in memory. Chapter 07's binary tree collapsed so that a
// node has up to 8 children, in two layouts: plain float boxes (WideNode<4>, WideNode<8>) and
// the compressed 80-byte node of Ylitie, Karras & Laine 2017 (CompressedNode), whose child
// boxes are 8-bit grid coordinates rounded outward. Triangles are chapter 08's 16-byte records,
// or the same data packed into 40 bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include <vector_types.h> // CUDA's float4, on host and device

#include "bvh.h"
#include "packed_bvh.h"
#include "rt/hd.h"

namespace rt::ch09 {

using ch04::TriangleF;
using ch07::Aabb;

// A node has one slot per octant of ray directions, so at most 8 children.
inline constexpr int k_slots = 8;
// The most triangles in a leaf (the paper's limit): 8 leaves of 3 use the 24 low bits of a
// node's hit mask, the 8 high bits are its interior children.
inline constexpr int k_max_leaf_triangles = 3;
inline constexpr int k_triangle_bits = k_slots * k_max_leaf_triangles;
static_assert(k_triangle_bits + k_slots == 32, "one 32-bit mask holds every hit of a node");

// [listing:child_meta]
// One byte per child says what it is and which bits of the node's 32-bit hit mask it sets
// when the ray enters its box (the paper's encoding):
//   0000 0000            an empty slot: no bits
//   001 11sss = 24 + s   an interior child in octant slot s: bit 24 + (s ^ octant_inverse)
//   ccc ooooo            a leaf: ccc its triangle count in unary (001, 011 or 111), ooooo the
//                        offset of its first triangle from the node's triangle_base (0..23):
//                        bits offset .. offset + count - 1
// A leaf's offset is at most 23, so bits 3 and 4 of the low five are both set only for an
// interior child.
RT_HD constexpr std::uint8_t interior_meta(int slot) {
  return static_cast<std::uint8_t>(0x20 | (k_triangle_bits + slot));
}
RT_HD constexpr std::uint8_t leaf_meta(int count, int offset) {
  return static_cast<std::uint8_t>((((1 << count) - 1) << 5) | offset);
}
RT_HD constexpr bool is_interior_meta(std::uint8_t meta) { return (meta & 0x18) == 0x18; }

// The bits a child sets in the hit mask when the ray enters it. An interior child's slot is
// XORed with the ray's octant_inverse (7 - its octant), so that the slot meant to be visited
// first by rays of this octant lands on the highest bit.
RT_HD constexpr unsigned meta_bits(std::uint8_t meta, unsigned octant_inverse) {
  const unsigned shift = (meta & 31u) ^ (is_interior_meta(meta) ? octant_inverse : 0u);
  return (unsigned(meta) >> 5) << shift;
}
// [/listing:child_meta]

// [listing:wide_node]
// A node of N children with plain float boxes, the boxes stored by coordinate (all lo.x, then
// all lo.y, ...) so that one vector instruction tests several children. N = 8: 224 bytes.
//
//   byte 0 .. 24N-1       lo_x[N] lo_y[N] lo_z[N] hi_x[N] hi_y[N] hi_z[N]  (float32)
//   byte 24N .. 24N+7     child_base, triangle_base                        (int32)
//   byte 24N+8 .. 25N+7   meta[N]: what each child is (see interior_meta)
//   byte 25N+8            imask: bit s set where slot s holds an interior child
//   then padding (alignas) to a multiple of 16 bytes, so the node is read in 16-byte loads
//
// The children are stored in the order of their octant slots, the empty slots left out (an
// interior child's slot is in its meta byte), then empty children: an empty box and meta 0.
// A node's interior children are consecutive nodes from child_base, in slot order: the one in
// slot s is node child_base + (interior children in slots below s). Its leaves' triangles are
// consecutive records from triangle_base.
template <int N> struct alignas(16) WideNode {
  static_assert(N >= 2 && N <= k_slots);
  static constexpr int k_width = N;
  float lo_x[N], lo_y[N], lo_z[N];
  float hi_x[N], hi_y[N], hi_z[N];
  int child_base;
  int triangle_base;
  std::uint8_t meta[N];
  std::uint8_t imask;
};
static_assert(sizeof(WideNode<8>) == 224 && sizeof(WideNode<4>) == 112);
static_assert(offsetof(WideNode<8>, child_base) == 192 && offsetof(WideNode<8>, meta) == 200);
static_assert(offsetof(WideNode<8>, imask) == 208);
// [/listing:wide_node]

// Child c's box into a node's six coordinate arrays (a WideNode, or the CPU's node).
template <class Node> RT_HD inline void set_child_box(Node& node, int c, const Aabb& box) {
  node.lo_x[c] = box.lo.x;
  node.lo_y[c] = box.lo.y;
  node.lo_z[c] = box.lo.z;
  node.hi_x[c] = box.hi.x;
  node.hi_y[c] = box.hi.y;
  node.hi_z[c] = box.hi.z;
}

// [listing:compressed_node]
// The compressed node, 80 bytes (five 16-byte loads) for 8 children:
//
//   byte  0..11  origin[3]     the grid's corner: the node box's lo (float32)
//   byte 12..14  exponent[3]   per axis the grid step 2^(exponent - 127), a float's exponent
//   byte 15      imask         bit s set where slot s holds an interior child
//   byte 16..19  child_base    first interior child (int32)
//   byte 20..23  triangle_base first triangle record of its leaves (int32)
//   byte 24..31  meta[8]       what each child is (see interior_meta)
//   byte 32..55  q_lo_x[8] q_lo_y[8] q_lo_z[8]  child box lo, in grid steps from origin
//   byte 56..79  q_hi_x[8] q_hi_y[8] q_hi_z[8]  child box hi, likewise
//
// As in WideNode, the children are stored in slot order, empty slots left out (an interior
// child's slot is in its meta byte). Child c's box along x is [dequantise(q_lo_x[c]),
// dequantise(q_hi_x[c])], computed by the traversal exactly as the build computed it.
struct alignas(16) CompressedNode {
  static constexpr int k_width = k_slots;
  float origin[3];
  std::uint8_t exponent[3];
  std::uint8_t imask;
  int child_base;
  int triangle_base;
  std::uint8_t meta[k_slots];
  std::uint8_t q_lo_x[k_slots], q_lo_y[k_slots], q_lo_z[k_slots];
  std::uint8_t q_hi_x[k_slots], q_hi_y[k_slots], q_hi_z[k_slots];
};
static_assert(sizeof(CompressedNode) == 80, "the node layout above is 80 bytes");
static_assert(offsetof(CompressedNode, exponent) == 12 &&
              offsetof(CompressedNode, imask) == 15);
static_assert(offsetof(CompressedNode, child_base) == 16);
static_assert(offsetof(CompressedNode, meta) == 24 && offsetof(CompressedNode, q_lo_x) == 32);
static_assert(offsetof(CompressedNode, q_hi_x) == 56);
// [/listing:compressed_node]

// The grid step of an exponent byte: 2^(exponent - 127), the float with those exponent bits.
RT_HD inline float grid_step(std::uint8_t exponent) {
  const std::uint32_t bits = std::uint32_t(exponent) << 23;
  float step;
  std::memcpy(&step, &bits, sizeof step);
  return step;
}

// [listing:dequantise]
// A quantised plane back in float: q * step + origin. The product is exact (q has 8 bits,
// step is a power of two between 2^-126 and 2^120, so q * step is a normal float or 0), so
// the only rounding is the addition's: the GPU's fused multiply-add and the CPU's multiply
// then add give the same float, and the build, which chose q with this very function,
// guarantees that float lies on the outer side of the child's exact box.
RT_HD inline float dequantise(std::uint8_t q, float step, float origin) {
  return float(q) * step + origin;
}
// [/listing:dequantise]
inline constexpr int k_min_grid_exponent = -126; // the smallest normal float's
inline constexpr int k_max_grid_exponent = 120;  // 255 * 2^120 < the largest float

#if defined(__CUDA_ARCH__)
// A node read whole on the GPU, in 16-byte loads (chapter 08's fastest path).
template <class Node> __device__ Node load_node(const Node* p) {
  static_assert(sizeof(Node) % 16 == 0 && alignof(Node) == 16);
  const float4* records = reinterpret_cast<const float4*>(p);
  Node node;
#pragma unroll
  for (int r = 0; r < int(sizeof(Node) / 16); ++r) {
    const float4 record = records[r];
    std::memcpy(reinterpret_cast<char*>(&node) + 16 * r, &record, 16);
  }
  return node;
}
#endif

// An int's bits as a float, ch08::bits_as_int's inverse: the id rides in a coordinate's lane.
RT_HD inline float int_bits_as_float(int i) {
#if defined(__CUDA_ARCH__)
  return __int_as_float(i);
#else
  float f;
  std::memcpy(&f, &i, sizeof f);
  return f;
#endif
}

// [listing:triangle_stores]
// The triangles in the order of the leaves, as the traversal reads them and every builder
// writes them: 36 bytes of coordinates and the mesh's 4-byte id, in one of two layouts.
//
// Chapter 08's records, 48 bytes: three 16-byte loads, 8 bytes of padding.
//   record 0: v0.x v0.y v0.z id    record 1: v1.x v1.y v1.z -    record 2: v2.x v2.y v2.z -
struct AlignedTriangles {
  using Record = float4;
  static constexpr int k_records = 3;
  RT_HD static TriangleF triangle(const Record* r) {
    return ch08::triangle_from_records(r[0], r[1], r[2]);
  }
  RT_HD static int id(const Record* r) { return ch08::bits_as_int(r[0].w); }
  RT_HD static void write(Record* r, const TriangleF& t, int id) {
    r[0] = {t.v0.x, t.v0.y, t.v0.z, int_bits_as_float(id)};
    r[1] = {t.v1.x, t.v1.y, t.v1.z, 0.0f};
    r[2] = {t.v2.x, t.v2.y, t.v2.z, 0.0f};
  }
};

// The same 40 bytes without the padding: five 8-byte loads.
//   v0.x v0.y | v0.z id | v1.x v1.y | v1.z v2.x | v2.y v2.z
struct PackedTriangles {
  using Record = float2;
  static constexpr int k_records = 5;
  RT_HD static TriangleF triangle(const Record* r) {
    const float2 a = r[0], b = r[1], c = r[2], d = r[3], e = r[4];
    return {{a.x, a.y, b.x}, {c.x, c.y, d.x}, {d.y, e.x, e.y}};
  }
  RT_HD static int id(const Record* r) { return ch08::bits_as_int(r[1].y); }
  RT_HD static void write(Record* r, const TriangleF& t, int id) {
    r[0] = {t.v0.x, t.v0.y};
    r[1] = {t.v0.z, int_bits_as_float(id)};
    r[2] = {t.v1.x, t.v1.y};
    r[3] = {t.v1.z, t.v2.x};
    r[4] = {t.v2.y, t.v2.z};
  }
};
// [/listing:triangle_stores]

// What the traversal reads: nodes of one type and the triangles in one of the stores above.
// Host or device pointers.
template <class Node, class Triangles = AlignedTriangles> struct WideTreeView {
  using Record = typename Triangles::Record;
  const Node* nodes = nullptr;
  const Record* triangles = nullptr;
  int node_count = 0; // 0 only for a mesh with no triangles
  // Host trees only: the same triangles by coordinate, nine columns of column_stride floats
  // (v0.x v0.y v0.z v1.x ... v2.z, column c from columns + c * column_stride), for the CPU's
  // eight-at-once triangle test (test_triangles, wide_traverse.h). Null on the GPU.
  const float* columns = nullptr;
  int column_stride = 0;

  // The GPU copies a node into registers in 16-byte loads; the CPU reads it where it lies
  // (a copy of 224 bytes per node read would cost more than the test).
#if defined(__CUDA_ARCH__)
  __device__ Node node(int i) const { return load_node(nodes + i); }
#else
  const Node& node(int i) const { return nodes[i]; }
#endif
  RT_HD TriangleF triangle(int k) const {
    return Triangles::triangle(triangles + Triangles::k_records * k);
  }
  RT_HD int triangle_id(int k) const {
    return Triangles::id(triangles + Triangles::k_records * k);
  }
};

// [listing:stack_bound]
// The traversal's stack (wide_traverse.h) holds groups of children still to visit, at most one
// group per level of the tree above the node being tested: a group is pushed only when the
// traversal descends from it, and it is popped before any group of a shallower level is
// touched again. So a tree whose deepest node lies at depth D needs at most D entries.
// Every wide node is a node of chapter 07's binary tree and its wide children lie strictly
// below it there, so its wide depth is at most its binary depth, which chapter 07's build keeps
// within k_max_bvh_depth - 1 (its depth bound, proved in bvh_build.cpp). The collapse checks
// the depth of every tree it makes against this size all the same.
inline constexpr int k_wide_stack_size = 63; // entries of 8 bytes
static_assert(k_wide_stack_size >= ch07::k_max_bvh_depth - 1,
              "the stack must cover the deepest tree chapter 07's build may make");
// [/listing:stack_bound]

// What the report prints about a wide tree.
struct WideStats {
  int nodes = 0;
  int leaves = 0;
  int depth = 0;                   // deepest node (the root is at depth 0)
  double children_per_node = 0.0;  // non-empty slots, on average
  double triangles_per_leaf = 0.0; // on average
  double sah_cost = 0.0;           // the collapse's cost model (collapse.h), over the root area
  double build_ms = 0.0;           // the binary build, the collapse, the stored layout
  double bytes_per_triangle = 0.0; // nodes and triangle records over the mesh's triangles
  // The binary tree it was collapsed from. Spatial splits (sbvh) reference a triangle from
  // several leaves, so a tree may hold more triangle records than the mesh has triangles.
  ch07::SplitMethod split = ch07::SplitMethod::sah;
  long long triangles = 0;  // the mesh's
  long long references = 0; // triangle records in the leaves: the triangles, unless sbvh
};

// A wide tree, owned in host memory.
template <class Node, class Triangles = AlignedTriangles> struct WideTree {
  using View = WideTreeView<Node, Triangles>;
  std::vector<Node> nodes; // node 0 is the root
  std::vector<typename Triangles::Record> triangles;
  std::vector<float> columns; // host only (see WideTreeView); not in stats.bytes_per_triangle
  int column_stride = 0;
  WideStats stats;

  View view() const {
    return {nodes.data(), triangles.data(), static_cast<int>(nodes.size()),
            columns.empty() ? nullptr : columns.data(), column_stride};
  }
};

using Wide4Bvh = WideTree<WideNode<4>>;
using Wide4PackedBvh = WideTree<WideNode<4>, PackedTriangles>;
using Wide8Bvh = WideTree<WideNode<8>>;
using CompressedBvh = WideTree<CompressedNode>;

} // namespace rt::ch09
