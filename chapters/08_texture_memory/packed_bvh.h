// Chapter 08: chapter 07's tree in 16-byte records, and the ways a traversal reads it. Each
// type below has the node(), triangle(), triangle_id() and node_count that chapter 07's
// trace_bvh asks of a tree, so the traversal itself is unchanged: only its loads differ.
#pragma once

#include <cstring>
#include <vector>

#include <vector_types.h> // CUDA's float4: four floats, 16-byte aligned, on host and device

#include "bvh.h"
#include "rt/hd.h"

#if defined(__CUDACC__)
#include <texture_indirect_functions.h> // tex1Dfetch<T> on a texture object
#endif

namespace rt::ch08 {

using ch04::TriangleF;
using ch07::Bvh;
using ch07::BvhNode;
using ch07::BvhView;

// [listing:packed_layout]
// The packed layout: 16-byte records, each fetched by one vector load.
//
//   node i       records 4i .. 4i+3: its 64 bytes exactly as chapter 07 lays them out
//                  r0 = box[0].lo.xyz, box[0].hi.x     r1 = box[0].hi.yz, box[1].lo.xy
//                  r2 = box[1].lo.z, box[1].hi.xyz     r3 = first[0..1], count[0..1] (int bits)
//   triangle k   records 3k .. 3k+2: v0 and the mesh's triangle number (int bits in w),
//                  v1, v2 (w = 0): 48 bytes instead of 36 + a 4-byte id in another array
inline constexpr int k_node_records = 4;
inline constexpr int k_triangle_records = 3;

struct PackedBvh {
  std::vector<float4> nodes;     // k_node_records per node
  std::vector<float4> triangles; // k_triangle_records per triangle, in leaf order
  int node_count = 0;
};
// [/listing:packed_layout]

static_assert(sizeof(BvhNode) == k_node_records * sizeof(float4));
static_assert(alignof(float4) == 16);

PackedBvh pack_bvh(const Bvh& bvh);

// A float's bits as an int and back (the ids and child links ride in float lanes).
RT_HD inline int bits_as_int(float f) {
#if defined(__CUDA_ARCH__)
  return __float_as_int(f);
#else
  int i;
  std::memcpy(&i, &f, sizeof i);
  return i;
#endif
}

RT_HD inline BvhNode node_from_records(float4 r0, float4 r1, float4 r2, float4 r3) {
  BvhNode n;
  n.box[0].lo = {r0.x, r0.y, r0.z};
  n.box[0].hi = {r0.w, r1.x, r1.y};
  n.box[1].lo = {r1.z, r1.w, r2.x};
  n.box[1].hi = {r2.y, r2.z, r2.w};
  n.first[0] = bits_as_int(r3.x);
  n.first[1] = bits_as_int(r3.y);
  n.count[0] = bits_as_int(r3.z);
  n.count[1] = bits_as_int(r3.w);
  return n;
}

RT_HD inline TriangleF triangle_from_records(float4 r0, float4 r1, float4 r2) {
  return {{r0.x, r0.y, r0.z}, {r1.x, r1.y, r1.z}, {r2.x, r2.y, r2.z}};
}

// [listing:read_only_load]
// One object through the read-only data cache, word by word: __ldg on the GPU compiles to
// LDG.E.CONSTANT. The CPU has no such cache; there it is a plain read.
template <class T> RT_HD T load_read_only(const T* p) {
#if defined(__CUDA_ARCH__)
  static_assert(sizeof(T) % 4 == 0, "read as 4-byte words");
  constexpr int k_words = sizeof(T) / 4;
  unsigned int words[k_words];
  const unsigned int* from = reinterpret_cast<const unsigned int*>(p);
#pragma unroll
  for (int w = 0; w < k_words; ++w) words[w] = __ldg(from + w);
  T out;
  std::memcpy(&out, words, sizeof(T));
  return out;
#else
  return *p;
#endif
}

// A 16-byte record in one read-only vector load: LDG.E.128.CONSTANT.
RT_HD inline float4 load_read_only(const float4* p) {
#if defined(__CUDA_ARCH__)
  return __ldg(p);
#else
  return *p;
#endif
}
// [/listing:read_only_load]

// Path "ldg": chapter 07's layout, every load read-only.
struct ReadOnlyBvh {
  const BvhNode* nodes = nullptr;
  const TriangleF* triangles = nullptr;
  const int* triangle_ids = nullptr;
  int node_count = 0;

  RT_HD BvhNode node(int i) const { return load_read_only(nodes + i); }
  RT_HD TriangleF triangle(int k) const { return load_read_only(triangles + k); }
  RT_HD int triangle_id(int k) const { return load_read_only(triangle_ids + k); }
};

inline ReadOnlyBvh read_only(const BvhView& v) {
  return {v.nodes, v.triangles, v.triangle_ids, v.node_count};
}

// [listing:record_sources]
// Where the 16-byte records come from: three sources, one PackedTree over each.
struct GlobalRecords { // plain loads: LDG.E.128
  const float4* nodes = nullptr;
  const float4* triangles = nullptr;
  RT_HD float4 node(int r) const { return nodes[r]; }
  RT_HD float4 triangle(int r) const { return triangles[r]; }
};

struct ReadOnlyRecords { // through the read-only data cache: LDG.E.128.CONSTANT
  const float4* nodes = nullptr;
  const float4* triangles = nullptr;
  RT_HD float4 node(int r) const { return load_read_only(nodes + r); }
  RT_HD float4 triangle(int r) const { return load_read_only(triangles + r); }
};

#if defined(__CUDACC__)
struct TextureRecords { // through the texture unit: TEX/TLD (a GPU-only path)
  cudaTextureObject_t nodes = 0;
  cudaTextureObject_t triangles = 0;
  __device__ float4 node(int r) const { return tex1Dfetch<float4>(nodes, r); }
  __device__ float4 triangle(int r) const { return tex1Dfetch<float4>(triangles, r); }
};
#endif

template <class Records> struct PackedTree {
  Records records;
  int node_count = 0;

  RT_HD BvhNode node(int i) const {
    const int r = k_node_records * i;
    return node_from_records(records.node(r), records.node(r + 1), records.node(r + 2),
                             records.node(r + 3));
  }
  RT_HD TriangleF triangle(int k) const {
    const int r = k_triangle_records * k;
    return triangle_from_records(records.triangle(r), records.triangle(r + 1),
                                 records.triangle(r + 2));
  }
  RT_HD int triangle_id(int k) const {
    return bits_as_int(records.triangle(k_triangle_records * k).w);
  }
};
// [/listing:record_sources]

// The packed tree in host memory, read by the CPU.
inline PackedTree<GlobalRecords> host_view(const PackedBvh& p) {
  return {{p.nodes.data(), p.triangles.data()}, p.node_count};
}

} // namespace rt::ch08
