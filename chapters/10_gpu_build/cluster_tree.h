// Chapter 10: the tree the clustering builders make (PLOC in ploc.cu, H-PLOC in hploc.cu),
// before it is laid out as chapter 07's: its nodes numbered as the merges make them, and where
// each lands in chapter 07's depth-first arrays, counted on the way up.
#pragma once

#include "bvh.h"
#include "rt/hd.h"

namespace rt::ch10 {

// An interior node of the clustering: its two clusters, left (earlier in Morton order) first.
struct ClusterPair {
  int child[2];
};

// The clustering's nodes. Numbers 0 .. n-1 are the leaves in Morton order, n + j is interior
// node j, numbered in the order the merges make them (PLOC: round by round; H-PLOC: by an
// atomic counter, so the numbers change from run to run, the tree they describe does not).
struct ClusterTree {
  int n;
  ch07::Aabb* boxes;  // 2n - 1: every node's box
  int* leaf_counts;   // 2n - 1: leaves below every node
  ClusterPair* nodes; // n - 1 interior nodes
  int* parents;       // 2n - 1: 2 * interior node + child slot; -1 for the root
};

// [listing:place_on_way_up]
// Node x's place in chapter 07's arrays, counted on the way up as for the LBVH: a left child
// comes right after its parent, a right child after the parent and the whole left subtree (its
// leaves less one interior nodes); a leaf's triangle slot, or an interior node's first one, is
// the number of leaves in the left subtrees passed. The walk gives up past `deepest` levels.
struct WayUp {
  int index;     // in chapter 07's node array
  int leaf_slot; // of the node's first leaf
  bool too_deep;
};
RT_HD inline WayUp place_on_way_up(const ClusterTree& tree, int x, int deepest) {
  WayUp up{0, 0, false};
  for (int depth = 0; tree.parents[x] >= 0;) {
    if (++depth > deepest) return {0, 0, true};
    const int parent = tree.parents[x] >> 1;
    const int left = tree.nodes[parent].child[0];
    const bool right = (tree.parents[x] & 1) != 0;
    up.index += right ? tree.leaf_counts[left] : 1;
    up.leaf_slot += right ? tree.leaf_counts[left] : 0;
    x = tree.n + parent;
  }
  return up;
}
// [/listing:place_on_way_up]

} // namespace rt::ch10
