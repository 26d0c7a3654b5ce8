// Chapter 10: treelet restructuring (Karras & Aila 2013), a pass that makes a finished tree
// better. A treelet is a node and the few nodes just below it: its root, its own leaves (up to
// seven nodes of the tree, each with its subtree kept whole) and the interior nodes between
// them. Of all the binary trees over those leaves the pass finds the one whose interior boxes
// have the least total area, by dynamic programming over the subsets of the leaves, and
// rewires the treelet into it, reusing its interior nodes. With one triangle per leaf the SAH
// cost of the whole tree is a constant plus the areas of its interior boxes, so no treelet
// ever makes it worse. One walk from the leaves up, as the bottom-up boxes go (refit.h): the
// second thread to reach a node restructures the treelet under it, whose subtrees are final
// by then. Any order of the threads gives the same tree.
#pragma once

#include <limits>

#include "cluster_tree.h"
#include "hploc.h"      // count_bits
#include "hploc_walk.h" // load_published, lowest_set_bit
#include "refit.h"      // second_arrival
#include "rt/hd.h"

namespace rt::ch10 {

// Leaves of a treelet, and the subsets of them the search weighs.
inline constexpr int k_treelet_leaves = 7;
inline constexpr int k_treelet_subsets = 1 << k_treelet_leaves;

// A treelet as it was found: its leaves, and its interior nodes with their children, each
// child a leaf's place in `leaf` (0 and up) or an interior node's (~k for node[k]). node[0] is
// the root; node[k], k >= 1, is the k-th leaf opened, whose children took its place and the
// next free one.
struct Treelet {
  int leaf_count = 0;
  int leaf[k_treelet_leaves];         // nodes of the tree
  Aabb box[k_treelet_leaves];         // their boxes
  int node[k_treelet_leaves - 1];     // interior nodes of the tree (numbers from n on)
  int child[k_treelet_leaves - 1][2]; // leaf places, or ~k
};

// The treelet under interior node `root` (a number from n on): its two children to start
// with, then, while it has fewer than seven leaves, the leaf of largest area that is an
// interior node of the tree is opened (the first of equal ones), its children becoming
// leaves. Reads what other threads wrote earlier in the walk.
RT_HD inline void open_treelet(const ClusterTree& tree, int root, Treelet& t) {
  t.node[0] = root;
  for (int c = 0; c < 2; ++c) {
    t.leaf[c] = load_published(&tree.nodes[root - tree.n].child[c]);
    t.box[c] = load_published(tree.boxes[t.leaf[c]]);
    t.child[0][c] = c;
  }
  t.leaf_count = 2;
  while (t.leaf_count < k_treelet_leaves) {
    int open = -1;
    float largest = -1.0f;
    for (int i = 0; i < t.leaf_count; ++i) {
      const float area = ordered_area(t.box[i]);
      if (t.leaf[i] >= tree.n && area > largest) {
        open = i;
        largest = area;
      }
    }
    if (open < 0) return; // every leaf a leaf of the tree
    const int k = t.leaf_count - 1, x = t.leaf[open], added = t.leaf_count;
    t.node[k] = x;
    for (int j = 0; j < k; ++j) // the child that was leaf `open` is now node k
      for (int c = 0; c < 2; ++c)
        if (t.child[j][c] == open) t.child[j][c] = ~k;
    for (int c = 0; c < 2; ++c) {
      const int place = c == 0 ? open : added;
      t.leaf[place] = load_published(&tree.nodes[x - tree.n].child[c]);
      t.box[place] = load_published(tree.boxes[t.leaf[place]]);
      t.child[k][c] = place;
    }
    ++t.leaf_count;
  }
}

// The treelet's cost of the leaves in `set` (a bit per leaf) under one node: their box's
// ordered area (hploc.h), as H-PLOC's merges price theirs.
RT_HD inline float subset_area(const Treelet& t, unsigned set) {
  Aabb box;
  for (int i = 0; i < t.leaf_count; ++i)
    if ((set >> i & 1u) != 0) box.grow(t.box[i]);
  return ordered_area(box);
}

// [listing:treelet_search]
// The best binary tree over a treelet's leaves. For every subset s of them (a bit per leaf),
// cost[s] is the least total area of the interior nodes of any tree over s, and split[s] the
// part holding s's lowest leaf in the best such tree: a subset's tree is its box over the
// best trees of some split in two, so
//     cost[s] = area(s) + min over splits s = p + q of cost[p] + cost[q],
// and a single leaf costs 0 (its subtree is not touched). Every part of s is a smaller
// subset, ready before s. Each split is weighed once, as the part holding the lowest leaf (p
// runs over those parts, all but s itself): 2^(k-1) - 1 splits for a subset of k leaves, 966
// over the 127 subsets of seven. Of equal costs the first found stays, on every backend.
RT_HD inline void search_subset(const Treelet& t, unsigned set, float* cost,
                                unsigned char* split) {
  const unsigned lowest = set & (~set + 1u), rest = set ^ lowest;
  if (rest == 0) {
    cost[set] = 0.0f;
    return;
  }
  float best = 0.0f;
  unsigned best_part = 0;
  for (unsigned q = rest; q != 0;) { // q: the part's other leaves, each subset of rest but rest
    q = (q - 1u) & rest;
    const unsigned part = lowest | q;
    const float c = cost[part] + cost[set ^ part];
    if (best_part == 0 || c < best) {
      best = c;
      best_part = part;
    }
  }
  cost[set] = subset_area(t, set) + best;
  split[set] = static_cast<unsigned char>(best_part);
}
// [/listing:treelet_search]

// The search's tables, one treelet at a time.
struct TreeletSearch {
  float cost[k_treelet_subsets];
  unsigned char split[k_treelet_subsets];
};

// The cost of the treelet's shape as it was, summed as search_subset sums a shape (the part
// holding the lowest leaf first), so that the search's cost is at most this one bit for bit.
RT_HD inline float treelet_cost_now(const Treelet& t) {
  unsigned cover[k_treelet_leaves - 1] = {}; // each interior node's leaves
  float cost[k_treelet_leaves - 1] = {};
  for (int k = t.leaf_count - 2; k >= 0; --k) { // children are opened after their parents
    unsigned part[2];
    float part_cost[2];
    for (int c = 0; c < 2; ++c) {
      const int child = t.child[k][c];
      part[c] = child >= 0 ? 1u << child : cover[~child];
      part_cost[c] = child >= 0 ? 0.0f : cost[~child];
    }
    cover[k] = part[0] | part[1];
    const int low = (cover[k] & (~cover[k] + 1u)) == (part[0] & (~part[0] + 1u)) ? 0 : 1;
    cost[k] = subset_area(t, cover[k]) + (part_cost[low] + part_cost[1 - low]);
  }
  return cost[0];
}

// Rewires the treelet under `root` into the tree `split` describes: the root keeps its
// number, the other interior nodes are given out in their order as the new tree needs them;
// boxes, leaf counts and links are written for each, the part holding the lowest leaf on the
// left. The root's box and count do not change.
RT_HD inline void rewire_treelet(const ClusterTree& tree, const Treelet& t,
                                 const unsigned char* split) {
  int leaves_of[k_treelet_leaves];
  for (int i = 0; i < t.leaf_count; ++i)
    leaves_of[i] = load_published(&tree.leaf_counts[t.leaf[i]]); // 1 for a leaf (StartLeaves)
  unsigned pending_set[k_treelet_leaves - 1];
  int pending_node[k_treelet_leaves - 1];
  int pending = 0, given = 1;
  pending_set[pending] = (1u << t.leaf_count) - 1u;
  pending_node[pending++] = t.node[0];
  while (pending > 0) {
    --pending;
    const unsigned set = pending_set[pending];
    const int node = pending_node[pending];
    const unsigned parts[2] = {split[set], set ^ split[set]};
    int child[2], leaves[2] = {0, 0};
    Aabb box;
    for (int c = 0; c < 2; ++c) {
      for (int i = 0; i < t.leaf_count; ++i)
        if ((parts[c] >> i & 1u) != 0) {
          leaves[c] += leaves_of[i];
          box.grow(t.box[i]);
        }
      if ((parts[c] & (parts[c] - 1u)) == 0) {
        child[c] = t.leaf[lowest_set_bit(parts[c])];
      } else {
        child[c] = t.node[given++];
        pending_set[pending] = parts[c];
        pending_node[pending++] = child[c];
      }
    }
    if (node != t.node[0]) {
      tree.boxes[node] = box;
      tree.leaf_counts[node] = leaves[0] + leaves[1];
    }
    link_children(tree, node - tree.n, child[0], child[1], leaves[0]);
  }
}

// Every subset of the treelet's leaves searched, in increasing order, by one thread.
RT_HD inline void search_treelet(const Treelet& t, TreeletSearch& s) {
  const unsigned all = (1u << t.leaf_count) - 1u;
  for (unsigned set = 1; set <= all; ++set) search_subset(t, set, s.cost, s.split);
}

// The treelet under interior node `root`, searched and, where the best tree is cheaper than
// the shape it has, rewired into it; by one thread. Returns whether it changed.
RT_HD inline bool restructure_treelet(const ClusterTree& tree, int root) {
  Treelet t;
  open_treelet(tree, root, t);
  if (t.leaf_count < 3) return false; // one shape only
  TreeletSearch s;
  search_treelet(t, s);
  if (!(s.cost[(1u << t.leaf_count) - 1u] < treelet_cost_now(t))) return false;
  rewire_treelet(tree, t, s.split);
  return true;
}

// The nodes round r (from 0) restructures: those with at least 7 * 2^r leaves below them.
// The first round looks at every treelet big enough to have seven leaves; later rounds, over
// a tree already improved, only at the larger ones, where most of the area is.
RT_HD constexpr int treelet_min_leaves(int round) { return k_treelet_leaves << round; }

// The walk of one round, a thread per leaf: up while the thread is the second to reach a
// node, restructuring the treelet under every node it completes that has at least
// `min_leaves` leaves below it. One counter per interior node, zero at the start. The CPU's
// threads run it as it is, each treelet searched by the thread that reached it.
struct RestructureTreelets {
  ClusterTree tree;
  unsigned* arrivals;
  int min_leaves;
  // One step up from x: whether the thread goes on, to the parent, now x.
  RT_HD bool climb(int& x) const {
    const int link = tree.parents[x];
    if (link < 0 || !second_arrival(&arrivals[link >> 1])) return false;
    x = tree.n + (link >> 1);
    return true;
  }
  RT_HD bool wants(int x) const { return load_published(&tree.leaf_counts[x]) >= min_leaves; }
  RT_HD void operator()(int leaf) const {
    for (int x = leaf; climb(x);)
      if (wants(x)) restructure_treelet(tree, x);
  }
};

// [listing:treelet_warp]
// On the GPU a thread alone would search its treelet's 966 splits while the other lanes of
// its warp, most of them done climbing, wait. So the warp searches together, as H-PLOC's warp
// merges (hploc_walk.h, and its Warp): every lane stays in the loop until none climbs; after
// each step up, the lanes that reached a treelet's root are taken one at a time, and the
// whole warp searches that treelet. The subsets go by their number of leaves, smallest
// first, each lane taking every 32nd; a subset's parts have fewer leaves, so each size needs
// only the sizes before it, and the warp steps together in between. With seven leaves the
// slowest lane of each size, one size after the other, weighs 177 splits instead of 966.
// The treelet and the tables are the warp's own, one copy that every lane reads (shared
// memory on the GPU): the owner opens the treelet, the lanes search it, the owner rewires it.
// The search sums and compares as the thread's does, so the tree is the same bit for bit.
struct TreeletTables {
  Treelet treelet;
  float cost[k_treelet_subsets];
  unsigned char split[k_treelet_subsets];
};
template <class Warp>
RT_HD void restructure_on_warp(Warp& warp, const RestructureTreelets& pass, int leaf, int lane,
                               TreeletTables& tables) {
  const ClusterTree& tree = pass.tree;
  int x = leaf;
  bool climbing = leaf < tree.n;
  while (warp.any(climbing)) {
    if (climbing) climbing = pass.climb(x);
    for (unsigned waiting = warp.ballot(climbing && pass.wants(x)); waiting != 0;
         waiting &= waiting - 1) {
      const int owner = lowest_set_bit(waiting);
      warp.sync(); // the tables' last reader, the owner before, is done with them
      if (lane == owner) open_treelet(tree, x, tables.treelet);
      warp.sync();
      const Treelet& t = tables.treelet;
      if (t.leaf_count < 3) continue;
      const unsigned all = (1u << t.leaf_count) - 1u;
      for (int size = 1; size <= t.leaf_count; ++size) {
        for (unsigned set = lane + 1u; set <= all; set += k_warp_lanes)
          if (count_bits(set) == size) search_subset(t, set, tables.cost, tables.split);
        warp.sync();
      }
      if (lane == owner && tables.cost[all] < treelet_cost_now(t))
        rewire_treelet(tree, t, tables.split);
    }
  }
}
// [/listing:treelet_warp]

} // namespace rt::ch10
