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
  int* left_leaves;   // 2n - 1: of a right child, the leaves of its left sibling; else 0
};

// Node `interior` (number n + interior) made of clusters left and right, linked to them: the
// parent links and the leaves a right child has to its left, which is all place_on_way_up
// reads on its way up.
RT_HD inline void link_children(const ClusterTree& tree, int interior, int left, int right,
                                int leaves_left) {
  tree.nodes[interior] = {{left, right}};
  tree.parents[left] = 2 * interior;
  tree.parents[right] = 2 * interior + 1;
  tree.left_leaves[left] = 0;
  tree.left_leaves[right] = leaves_left;
}

// [listing:place_on_way_up]
// Node x's place in chapter 07's arrays, counted on the way up as for the LBVH: a left child
// comes right after its parent, a right child after the parent and the whole left subtree (its
// leaves less one interior nodes); a leaf's triangle slot, or an interior node's first one, is
// the number of leaves in the left subtrees passed. The walk gives up past `deepest` levels.
// Each level costs one load that waits for the one before (the parent link); the left
// sibling's leaves come from an array of their own, read beside it, not from the parent's
// node and then the sibling's count, two more loads in a row.
struct WayUp {
  int index;     // in chapter 07's node array
  int leaf_slot; // of the node's first leaf
  bool too_deep;
};
RT_HD inline WayUp place_on_way_up(const ClusterTree& tree, int x, int deepest) {
  WayUp up{0, 0, false};
  for (int depth = 0;; ++depth) {
    const int link = tree.parents[x];
    if (link < 0) return up;
    if (depth + 1 > deepest) return {0, 0, true};
    const int before = tree.left_leaves[x]; // 0 for a left child
    up.index += (link & 1) != 0 ? before : 1;
    up.leaf_slot += before;
    x = tree.n + (link >> 1);
  }
}
// [/listing:place_on_way_up]

} // namespace rt::ch10
