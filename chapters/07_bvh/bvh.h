// Chapter 07: the bounding volume hierarchy as it lies in memory. One flat array of nodes in
// depth-first order, the triangles copied into the order of the leaves that hold them, and the
// map back to the mesh's own triangle numbers. The same arrays are read by the CPU (host
// pointers) and by the GPU (device pointers), through BvhView.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "mesh_gen.h"
#include "rt/hd.h"
#include "rt/vec.h"
#include "triangle.h"

namespace rt::ch07 {

using ch04::TriangleF;

// An axis-aligned box. The empty box has lo = +inf and hi = -inf: growing it by any point
// gives that point's box, and no ray enters it.
struct Aabb {
  Vec3f lo{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
           std::numeric_limits<float>::infinity()};
  Vec3f hi{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
           -std::numeric_limits<float>::infinity()};

  RT_HD void grow(Vec3f p) {
    lo = elementwise_min(lo, p);
    hi = elementwise_max(hi, p);
  }
  RT_HD void grow(const Aabb& b) {
    lo = elementwise_min(lo, b.lo);
    hi = elementwise_max(hi, b.hi);
  }
  RT_HD bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  RT_HD bool contains(const Aabb& b) const {
    return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && b.hi.x <= hi.x &&
           b.hi.y <= hi.y && b.hi.z <= hi.z;
  }
  // Half the surface area (the SAH only ever divides areas); 0 for an empty box.
  RT_HD float half_area() const {
    if (empty()) return 0.0f;
    const Vec3f e = hi - lo;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

// Half the surface area, in double, as every tree builder's cost takes it. Aabb::half_area
// multiplies floats, which overflows to infinity once a box is wider than about 1.8e19 (the
// square root of the largest float); every SAH cost is then inf / inf = NaN and the heuristic
// silently stops choosing. A double holds the product of any two floats.
RT_HD inline double half_area_of(const Aabb& box) {
  if (box.empty()) return 0.0;
  const Vec3d e = box.hi.as<double>() - box.lo.as<double>();
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

RT_HD inline Aabb bounds_of(const TriangleF& t) {
  Aabb box;
  box.grow(t.v0);
  box.grow(t.v1);
  box.grow(t.v2);
  return box;
}

// [listing:bvh_node]
// One interior node of the tree, 64 bytes: the boxes of its two children, so that a single
// node fetch tells the traversal which children the ray enters and which is nearer.
//
//   byte  0..23  box[0]    child 0's bounds: lo.x lo.y lo.z hi.x hi.y hi.z (float32)
//   byte 24..47  box[1]    child 1's bounds
//   byte 48..55  first[2]  interior child: index of its node; leaf child: its first triangle
//   byte 56..63  count[2]  0: the child is an interior node; n > 0: a leaf of n triangles
//
// Depth-first layout, as the thesis laid its tree out: an interior child 0 is always the very
// next node (first[0] == this node + 1), and child 1 sits at the offset first[1], after the
// whole subtree of child 0. Leaves are not nodes: a leaf child names a run of `count`
// consecutive triangles of Bvh::triangles. Node 0 is the root.
struct BvhNode {
  Aabb box[2];
  int first[2];
  int count[2];

  RT_HD bool is_leaf(int child) const { return count[child] > 0; }
};
static_assert(sizeof(BvhNode) == 64, "the node layout above is 64 bytes");
// [/listing:bvh_node]

// The deepest an interior node may sit (the root is at depth 0). Builds never exceed it, so a
// traversal stack of this many entries cannot overflow: the traversal pushes at most one entry
// per interior node on the path from the root to the node it is in.
inline constexpr int k_max_bvh_depth = 64;
// The most triangles a leaf may hold (what --leaf-size accepts).
inline constexpr int k_max_leaf_size = 64;

// What the traversal reads: host pointers on the CPU, device pointers on the GPU.
// The traversal reads a tree only through node(), triangle(), triangle_id() and node_count, so
// a later chapter can hand it the same tree stored another way (chapter 08's memory paths).
struct BvhView {
  const BvhNode* nodes = nullptr;       // node_count nodes; node 0 is the root
  const TriangleF* triangles = nullptr; // in leaf order
  const int* triangle_ids = nullptr;    // triangle_ids[k]: the mesh's number of triangles[k]
  int node_count = 0;                   // 0 only for a mesh with no triangles

  RT_HD const BvhNode& node(int i) const { return nodes[i]; }
  RT_HD const TriangleF& triangle(int k) const { return triangles[k]; }
  RT_HD int triangle_id(int k) const { return triangle_ids[k]; }
};

// median and sah give each triangle exactly one leaf; sbvh (spatial splits, sbvh_build.h) may
// reference a triangle from several leaves, never twice from one.
enum class SplitMethod { median, sah, sbvh };

const char* to_string(SplitMethod method);

struct BuildOptions {
  SplitMethod method = SplitMethod::sah;
  int max_leaf_size = 4; // 1..k_max_leaf_size
  int bins = 16;         // SAH candidate planes per axis are bins - 1; 2..256
  // sbvh only: the references may grow to (1 + split_budget) times the triangles; 0..4.
  double split_budget = 0.3;
  // Threads of the median and sah builds (sbvh builds on one); 0: the CPU backend's,
  // cpu_thread_count(). The tree is the same, bit for bit, for every count.
  int threads = 0;
};

// What the build report prints.
struct BuildStats {
  int nodes = 0;                     // interior nodes
  int leaves = 0;                    // leaf children
  int depth = 0;                     // deepest interior node (root = 0)
  std::vector<long long> leaf_sizes; // leaf_sizes[n]: leaves holding n triangles
  double sah_cost = 0.0; // expected cost of a random ray, in triangle tests (see bvh_build.h)
  double build_ms = 0.0;
  double bytes_per_triangle = 0.0; // nodes, triangle copies and ids, over the triangle count
  long long triangles = 0;         // the mesh's
  long long references = 0;        // triangle copies in leaves: the triangles, unless sbvh
  int spatial_splits = 0;          // sbvh: nodes split by a plane rather than by objects
  int threads = 1;                 // threads the build ran on (sbvh, and small meshes: 1)
};

// A built tree, owned in host memory.
struct Bvh {
  std::vector<BvhNode> nodes;
  std::vector<TriangleF> triangles; // the mesh's triangles, in leaf order (sbvh: references)
  std::vector<int> triangle_ids;    // the mesh's number of each
  Aabb bounds;                      // of the whole mesh
  BuildOptions options;
  BuildStats stats;

  BvhView view() const {
    return {nodes.data(), triangles.data(), triangle_ids.data(),
            static_cast<int>(nodes.size())};
  }
};

} // namespace rt::ch07
