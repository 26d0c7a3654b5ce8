// Chapter 10: the passes both of the chapter's builders share: triangle boxes, the centroids'
// bounds, Morton codes and the sort that puts the triangles in Morton order, and at the end the
// triangle copies in leaf order and the boxes from the bottom up. Included by the .cu files of
// the builders only (the GPU side needs nvcc).
#pragma once

#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_reduce.cuh>
#include <cub/device/device_scan.cuh>

#include "bvh.h"
#include "mesh_gen.h"
#include "morton.h"
#include "parallel.h"
#include "refit.h"
#include "triangles.h"

namespace rt::ch10::passes {

using ch04::IndexedTriangle;
using ch04::MeshView;

// The union of two boxes: what the reduction to the centroids' bounds joins.
struct JoinBoxes {
  RT_HD Aabb operator()(Aabb a, const Aabb& b) const {
    a.grow(b);
    return a;
  }
};

// The mesh where the backend reads it.
struct MeshArrays {
  BackendArray<Vec3f> vertices;
  BackendArray<IndexedTriangle> triangles;
  MeshArrays(Backend backend, const ch04::Mesh& mesh)
      : vertices(backend, std::span<const Vec3f>(mesh.vertices)),
        triangles(backend, std::span<const IndexedTriangle>(mesh.triangles)) {}
  MeshView view() {
    return {vertices.data(), triangles.data(), static_cast<int>(triangles.size())};
  }
};

// A box's centroid as a box of its own: what the reduction to the centroids' bounds joins.
RT_HD inline Aabb centroid_box(const Aabb& box) {
  Aabb centroid;
  centroid.grow(box_centroid(box));
  return centroid;
}

// Pass 1: each triangle's box, and its centroid for the reduction.
struct BoxTriangles {
  MeshView mesh;
  Aabb* boxes;
  Aabb* centroids;
  RT_HD void operator()(int i) const {
    const Aabb box = ch07::bounds_of(mesh.triangle(i));
    boxes[i] = box;
    centroids[i] = centroid_box(box);
  }
};

// [listing:centre_boxes]
// Pass 1 of an order of boxes (chapter 13's instances): the boxes are given, so only their
// centroids are made, as BoxTriangles makes a triangle's from its box.
struct CentreBoxes {
  const Aabb* boxes;
  Aabb* centroids;
  RT_HD void operator()(int i) const { centroids[i] = centroid_box(boxes[i]); }
};
// [/listing:centre_boxes]

// Pass 2: each box's Morton code (a triangle's box, or a given box), and its number beside it
// for the sort.
template <class Code> struct EncodeBoxes {
  const Aabb* boxes;
  const Aabb* centroid_bounds;
  Code* codes;
  int* ids;
  RT_HD void operator()(int i) const {
    codes[i] = morton_code<Code>(boxes[i], *centroid_bounds);
    ids[i] = i;
  }
};

// Sets a flag that many threads may set at once.
RT_HD inline void mark(int* flag) {
#if RT_ON_DEVICE
  *flag = 1;
#else
  __atomic_store_n(flag, 1, __ATOMIC_RELAXED);
#endif
}

// [listing:node_in_four_stores]
// A 64-byte node read or written in four 16-byte pieces on the GPU. BvhNode's members are
// floats and ints, so the compiler may only assume 4-byte alignment and moves it as sixteen
// 4-byte loads or stores: where a warp's lanes read or write scattered nodes, each of the
// sixteen is a memory request per lane. Arrays from cudaMalloc start 256-byte aligned, so
// every node of one sits on a 16-byte boundary and four requests do.
RT_HD inline BvhNode load_node(const BvhNode* from) {
#if RT_ON_DEVICE
  const float4* pieces = reinterpret_cast<const float4*>(from);
  float4 v[4];
  RT_UNROLL
  for (int k = 0; k < 4; ++k) v[k] = pieces[k];
  BvhNode node;
  memcpy(&node, v, sizeof node);
  return node;
#else
  return *from;
#endif
}
RT_HD inline void store_node(BvhNode* to, const BvhNode& node) {
#if RT_ON_DEVICE
  float4 v[4];
  memcpy(v, &node, sizeof node);
  float4* pieces = reinterpret_cast<float4*>(to);
  RT_UNROLL
  for (int k = 0; k < 4; ++k) pieces[k] = v[k];
#else
  *to = node;
#endif
}
// [/listing:node_in_four_stores]

// The triangle copies in leaf order.
struct GatherTriangles {
  MeshView mesh;
  const int* ids;
  TriangleF* triangles;
  RT_HD void operator()(int k) const { triangles[k] = mesh.triangle(ids[k]); }
};

// Parent links of a tree in chapter 07's layout (the refit of a tree this chapter did not
// build).
struct LinkParents {
  const BvhNode* nodes;
  int* parents;
  RT_HD void operator()(int i) const {
    for (int c = 0; c < 2; ++c)
      if (!nodes[i].is_leaf(c) && nodes[i].first[c] >= 0)
        parents[nodes[i].first[c]] = 2 * i + c;
    if (i == 0) parents[0] = -1;
  }
};

template <class Leaves> struct RefitNodes {
  RefitView<Leaves> tree;
  RT_HD void operator()(int i) const { refit_node(tree, i); }
};

// Scratch memory of CUB's reduce and sort, sized before the clock starts.
template <class Code> inline std::size_t cub_scratch_bytes(int n) {
  std::size_t reduce = 0, sort = 0;
  RT_CUDA_CHECK(cub::DeviceReduce::Reduce(nullptr, reduce, static_cast<Aabb*>(nullptr),
                                          static_cast<Aabb*>(nullptr), n, JoinBoxes{}, Aabb{}));
  RT_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(
      nullptr, sort, static_cast<Code*>(nullptr), static_cast<Code*>(nullptr),
      static_cast<int*>(nullptr), static_cast<int*>(nullptr), n));
  return std::max<std::size_t>({reduce, sort, 1});
}

// The union of the first n boxes of `items` into *out.
inline void reduce_bounds(Backend backend, const Aabb* items, int n, Aabb* out,
                          BackendArray<unsigned char>& scratch) {
  if (backend == Backend::cpu) {
    Aabb all;
    for (int i = 0; i < n; ++i) all = JoinBoxes{}(all, items[i]);
    *out = all;
    return;
  }
  std::size_t bytes = scratch.size();
  RT_CUDA_CHECK(
      cub::DeviceReduce::Reduce(scratch.data(), bytes, items, out, n, JoinBoxes{}, Aabb{}));
}

// [listing:sort_codes]
// The first n codes and triangle numbers sorted by code. Both sorts are stable and the numbers
// start in order, so equal codes keep their triangles in number order on both backends.
template <class Code>
inline void sort_by_code(Backend backend, int n, BackendArray<Code>& codes,
                         BackendArray<int>& ids, BackendArray<Code>& codes_out,
                         BackendArray<int>& ids_out, BackendArray<unsigned char>& scratch) {
  if (backend == Backend::cpu) {
    std::vector<std::pair<Code, int>> pairs(n);
    for (int i = 0; i < n; ++i) pairs[i] = {codes.data()[i], ids.data()[i]};
    std::stable_sort(pairs.begin(), pairs.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (int i = 0; i < n; ++i) std::tie(codes_out.data()[i], ids_out.data()[i]) = pairs[i];
    return;
  }
  constexpr int code_bits = 3 * CodeTraits<Code>::bits_per_axis; // the bits above are zero
  std::size_t bytes = scratch.size();
  RT_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(scratch.data(), bytes, codes.data(),
                                                codes_out.data(), ids.data(), ids_out.data(), n,
                                                0, code_bits));
}
// [/listing:sort_codes]

// The boxes of the first node_count nodes of a laid-out tree, from the bottom up (refit.h),
// the leaves boxed by `leaves`. `arrivals` holds a counter per node; made by the caller before
// its clock starts, so the pass times kernels only.
template <class Leaves>
inline void box_bottom_up(Backend backend, int node_count, BackendArray<BvhNode>& nodes,
                          const BackendArray<int>& parents, BackendArray<unsigned>& arrivals,
                          Leaves leaves) {
  arrivals.fill_bytes(0);
  for_each_index(backend, node_count,
                 RefitNodes<Leaves>{{nodes.data(), parents.data(), arrivals.data(), leaves}});
}

// The same for a tree of triangles, their copies in leaf order.
inline void box_bottom_up(Backend backend, BackendArray<BvhNode>& nodes,
                          const BackendArray<int>& parents,
                          const BackendArray<TriangleF>& triangles,
                          BackendArray<unsigned>& arrivals) {
  box_bottom_up(backend, static_cast<int>(nodes.size()), nodes, parents, arrivals,
                TriangleLeaves{triangles.data()});
}

// The root of a tree of one leaf: child 0 is the leaf, of the one item in leaf slot 0, and
// child 1 is empty (an empty box, which no ray enters, count 0 and first -1).
RT_HD inline BvhNode single_leaf_root(const Aabb& box) {
  BvhNode root;
  root.box[0] = box;
  root.box[1] = Aabb{};
  root.first[0] = 0;
  root.count[0] = 1;
  root.first[1] = -1;
  root.count[1] = 0;
  return root;
}

// A mesh of one triangle: chapter 07's root whose child 0 is the whole mesh's leaf.
inline ch07::Bvh single_leaf_tree(const ch04::Mesh& mesh) {
  ch07::Bvh bvh;
  bvh.triangles = {mesh.triangle(0)};
  bvh.triangle_ids = {0};
  bvh.bounds = ch07::bounds_of(bvh.triangles[0]);
  bvh.nodes = {single_leaf_root(bvh.bounds)};
  return bvh;
}

// The tree's bounds: the union of the root's two boxes, in that order. A reduction over the
// triangles' boxes would not do: min and max of +0 and -0 return whichever comes first, so a
// reduction in another order may give the other zero, where the bottom-up pass joins its boxes
// in one order on every backend. (The centroids' bounds may differ so; their cells do not.)
inline Aabb root_bounds(const ch07::Bvh& bvh) {
  Aabb box = bvh.nodes[0].box[0];
  box.grow(bvh.nodes[0].box[1]);
  return box;
}

// Device memory a build of n triangles needs, roughly, per triangle: the mesh, boxes and
// centroids, codes and numbers twice over, the Karras nodes or PLOC's clusters and the tree.
inline std::size_t device_bytes_per_triangle() {
  return 3 * sizeof(Vec3f) + sizeof(IndexedTriangle) + 3 * sizeof(Aabb) +
         4 * sizeof(std::uint64_t) + 8 * sizeof(int) + 4 * sizeof(int) + sizeof(BvhNode) +
         sizeof(TriangleF) + 2 * sizeof(unsigned) + 64;
}

// [listing:morton_order]
// Triangles, or boxes, in Morton order: the first passes of every builder of the chapter. The
// arrays are allocated when it is made, the passes run by sort() (a mesh's triangles) or
// sort_boxes() (boxes the caller keeps where the backend reads them), so a clock started in
// between times kernels only. Both end in the same three passes: the centroids' bounds, the
// codes, the sort.
template <class Code> struct MortonOrder {
  int n;                    // the items the last sort put in order
  MeshView mesh{};          // where the backend reads it; none for an order of boxes
  BackendArray<Aabb> boxes; // each triangle's box; empty for an order of boxes
  BackendArray<Aabb> centroids, centroid_bounds;
  BackendArray<Code> codes, sorted_codes;
  BackendArray<int> ids, sorted_ids;
  BackendArray<unsigned char> scratch;

  // The order of a mesh's triangles.
  MortonOrder(Backend backend, MeshView m)
      : MortonOrder(backend, m.triangle_count, m.triangle_count) {
    mesh = m;
  }
  // The order of up to `capacity` boxes, given to sort_boxes.
  MortonOrder(Backend backend, int capacity) : MortonOrder(backend, capacity, 0) {}

  void sort() {
    for_each_index(backend_, n, BoxTriangles{mesh, boxes.data(), centroids.data()});
    encode_and_sort(boxes.data());
  }
  void sort_boxes(const Aabb* given, int count) {
    n = count;
    for_each_index(backend_, n, CentreBoxes{given, centroids.data()});
    encode_and_sort(given);
  }

private:
  MortonOrder(Backend backend, int capacity, int triangle_count)
      : n(capacity), boxes(backend, triangle_count), centroids(backend, capacity),
        centroid_bounds(backend, 1), codes(backend, capacity), sorted_codes(backend, capacity),
        ids(backend, capacity), sorted_ids(backend, capacity),
        scratch(backend, backend == Backend::gpu ? cub_scratch_bytes<Code>(capacity) : 0),
        backend_(backend) {}

  void encode_and_sort(const Aabb* items) {
    reduce_bounds(backend_, centroids.data(), n, centroid_bounds.data(), scratch);
    for_each_index(backend_, n,
                   EncodeBoxes<Code>{items, centroid_bounds.data(), codes.data(), ids.data()});
    sort_by_code(backend_, n, codes, ids, sorted_codes, sorted_ids, scratch);
  }

  Backend backend_;
};
// [/listing:morton_order]

} // namespace rt::ch10::passes
