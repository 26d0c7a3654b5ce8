// Chapter 10: a tree in chapter 07's layout kept where the backend reads it, each node's parent
// beside it: what the builders make before anything goes to the host, what the refit and the
// collapse to a wide tree (wide_collapse.h) read, so that a frame's tree never leaves the GPU.
#pragma once

#include "bvh.h"
#include "rt/backend.h"
#include "rt/backend_array.h"
#include "triangles.h"

namespace rt::ch10 {

struct TreeArrays {
  BackendArray<ch07::BvhNode> nodes;
  BackendArray<int> parents;               // 2 * parent + child slot; -1 for the root
  BackendArray<ch04::TriangleF> triangles; // in leaf order
  BackendArray<int> triangle_ids;          // the mesh's number of each
  BackendArray<unsigned> arrivals;         // the bottom-up pass's counters, one per node

  TreeArrays() = default;
  TreeArrays(Backend backend, int node_count, int triangle_count)
      : nodes(backend, node_count), parents(backend, node_count),
        triangles(backend, triangle_count), triangle_ids(backend, triangle_count),
        arrivals(backend, node_count) {}
};

// `bvh` (it passes chapter 07's checker) on the backend, its parent links found there.
TreeArrays upload_tree(Backend backend, const ch07::Bvh& bvh);

// New boxes for the tree after the mesh's vertices moved: the triangle copies gathered again
// from `mesh` (backend pointers, the tree's triangles), the boxes from the bottom up
// (refit.h). The passes only: on the GPU they are queued and not waited for.
void refit_tree(Backend backend, TreeArrays& tree, ch04::MeshView mesh);

} // namespace rt::ch10
