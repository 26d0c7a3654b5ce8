// Chapter 10: H-PLOC (Benthin, Meister, Barczak, Parker & Wald 2024), the pieces both backends
// share. One bottom-up walk over the LBVH's hierarchy carries, for every subtree, a short list
// of clusters instead of one node; where a list grows past a threshold, PLOC runs inside it.
// On the GPU a warp merges a list together, one cluster per lane; on CPU threads the same
// steps run with the lanes in a loop (merge_cluster_list). hploc_walk.h has the walk itself,
// gpu_build.h the builder.
#pragma once

#include <cstdint>
#include <limits>

#include "bvh.h"
#include "cluster_tree.h"
#include "gpu_build.h"
#include "karras.h"
#include "rt/hd.h"

namespace rt::ch10 {

using ch07::Aabb;

// A box's half area as the builders compare it: a NaN (an area of inf * 0, on coordinates
// near the float range's end) counts as infinity, so that the areas are totally ordered and a
// choice depends on nothing but them.
RT_HD inline float ordered_area(const Aabb& box) {
  const float area = box.half_area();
  return area <= std::numeric_limits<float>::max() ? area
                                                   : std::numeric_limits<float>::infinity();
}

// What merging two clusters costs: the ordered area of their union, the left one's box grown by
// the right one's, the same operations in the same order on every backend.
RT_HD inline float merge_cost(const Aabb& left, const Aabb& right) {
  Aabb merged = left;
  merged.grow(right);
  return ordered_area(merged);
}

// A list of clusters, one per lane, as the CPU keeps it (the GPU keeps lane k's in lane k's
// registers). Left to right in Morton order.
struct ClusterList {
  int count = 0;
  int id[k_warp_lanes];
  Aabb box[k_warp_lanes];
  int leaves[k_warp_lanes];
};

// [listing:hploc_order]
// The order in which a cluster weighs its candidates: the cheaper merge, and of equal ones the
// leftmost, as PLOC chooses. A total order (merge_cost has no NaN), so the choice is the same
// whichever order the candidates come in: the GPU's lanes meet them in another order than
// the CPU's loop.
RT_HD inline bool better_candidate(float cost, int place, float best_cost, int best) {
  return best < 0 || cost < best_cost || (cost == best_cost && place < best);
}
// [/listing:hploc_order]

// The nearest neighbour of the list's cluster in `lane`: the best candidate within `radius`
// places on either side.
inline int nearest_cluster(const ClusterList& list, int lane, int radius) {
  int best = -1;
  float best_cost = 0.0f;
  const int lo = lane - radius < 0 ? 0 : lane - radius;
  const int hi = lane + radius >= list.count ? list.count - 1 : lane + radius;
  for (int j = lo; j <= hi; ++j) {
    if (j == lane) continue;
    const float cost = j < lane ? merge_cost(list.box[j], list.box[lane])
                                : merge_cost(list.box[lane], list.box[j]);
    if (better_candidate(cost, j, best_cost, best)) {
      best = j;
      best_cost = cost;
    }
  }
  return best;
}

// Set bits of a word, on either backend.
RT_HD inline int count_bits(unsigned x) {
#if RT_ON_DEVICE
  return __popc(x);
#else
  return __builtin_popcount(x);
#endif
}

// The place of the p-th set bit of a mask (p from 0; the mask has more than p): where the
// p-th cluster that stays sits before the list closes up. A binary search for the lowest
// place with p + 1 set bits at or below it: five counts, the same on both backends.
RT_HD inline int nth_set_bit(unsigned mask, int p) {
  int lane = 0;
  for (int step = k_warp_lanes / 2; step > 0; step /= 2) {
    const int top = lane + step - 1; // bits 0 .. top
    const unsigned upto = top >= 31 ? ~0u : (2u << top) - 1u;
    if (count_bits(mask & upto) < p + 1) lane += step;
  }
  return lane;
}

// Lanes below `lane`: the mask that counts a lane's rank among the lanes set in a vote.
RT_HD inline unsigned lanes_below(int lane) { return (1u << lane) - 1u; }

// Interior node `node` (a number from n on) made of clusters left and right, the left one
// of `leaves_left` leaves.
RT_HD inline void write_cluster_node(const ClusterTree& tree, int node, int left, int right,
                                     const Aabb& box, int leaves, int leaves_left) {
  tree.boxes[node] = box;
  tree.leaf_counts[node] = leaves;
  link_children(tree, node - tree.n, left, right, leaves_left);
}

// Counts `count` new nodes and returns the number of the first (from 0; node n + first).
RT_HD inline int reserve_nodes(int* counter, int count) {
#if RT_ON_DEVICE
  return atomicAdd(counter, count);
#else
  return __atomic_fetch_add(counter, count, __ATOMIC_RELAXED);
#endif
}

// [listing:hploc_climb]
// A subtree on its way up the LBVH's hierarchy (Apetrei 2014): its sorted leaves first..last,
// where its right child starts (once it has two), and the common prefix (karras.h's delta) its
// range shares with the leaf just before it and with the leaf just after it, -1 past either
// end of the array. The two prefixes decide where its parent lies; the boundary with the
// longer one splits lower in the tree.
struct Climber {
  int first, last, split;
  int prefix_before, prefix_after;
};
RT_HD inline Climber start_climb(const std::uint32_t* codes, int n, int leaf) {
  return {leaf, leaf, 0, delta(codes, n, leaf, leaf - 1LL), delta(codes, n, leaf, leaf + 1LL)};
}

// What a node's slot holds before its first child arrives, and what the first leaves there:
// its far end in the high word, the prefix beyond that end (+1, so never negative) in the low.
inline constexpr unsigned long long k_no_far_end = ~0ull;
RT_HD inline unsigned long long far_end_word(int far_end, int prefix) {
  return static_cast<unsigned long long>(far_end) << 32 | static_cast<unsigned>(prefix + 1);
}

// One step up. The parent is the node of the boundary, first-1|first or last|last+1, whose
// prefix is the longer. The first of the parent's two children to arrive leaves its far end
// and the prefix beyond it in the parent's slot, and stops; the second takes them and goes on
// with the parent's whole range, so no thread reads a Morton code after its start. On the GPU
// one fence follows each exchange the thread goes on from: it orders the sibling's clusters,
// read next, after the exchange, and this thread's clusters, written before its next
// exchange, before that one (Warp::publish fences after a merge's writes too). The subtree's
// first exchange follows no write of this kernel, and after its last nothing follows.
RT_HD inline bool climb(int n, unsigned long long* far_ends, Climber& s) {
  const bool left_child = s.first == 0 || (s.last != n - 1 && s.prefix_after > s.prefix_before);
  const int parent = left_child ? s.last : s.first - 1;
  const unsigned long long mine = left_child ? far_end_word(s.first, s.prefix_before)
                                             : far_end_word(s.last, s.prefix_after);
#if RT_ON_DEVICE
  const unsigned long long other = atomicExch(&far_ends[parent], mine);
  if (other == k_no_far_end) return false; // the first to arrive: nothing follows
  __threadfence();
#else
  const unsigned long long other =
      __atomic_exchange_n(&far_ends[parent], mine, __ATOMIC_ACQ_REL);
  if (other == k_no_far_end) return false;
#endif
  const int far_end = static_cast<int>(other >> 32);
  const int prefix = static_cast<int>(other & 0xffffffffu) - 1;
  if (left_child) {
    s.split = s.last + 1;
    s.last = far_end;
    s.prefix_after = prefix;
  } else {
    s.split = s.first;
    s.first = far_end;
    s.prefix_before = prefix;
  }
  return true;
}
// [/listing:hploc_climb]

// The clusters of a subtree live in the cluster array from the start of its range: at most
// `threshold` of them, ended by -1 where they are fewer than the slots a reader looks at (the
// range's size, or the threshold if that is less). A range never merged still holds its
// leaves, 0 .. size-1 places from its start, as the array began.
RT_HD inline int slots_to_read(int range_size, int threshold) {
  return range_size < threshold ? range_size : threshold;
}

// Whether the subtree over first..last, just completed, has its list looked at: when it may
// hold more clusters than a list may pass up, or may hold its children's lists with a gap
// between them, or is the root, which ends with one cluster.
RT_HD inline bool gathers(int first, int last, int n, int threshold) {
  return last - first + 1 > threshold || (first == 0 && last == n - 1);
}

// PLOC inside a list, the lanes of a warp in a loop: every cluster finds its nearest
// neighbour, pairs that chose each other merge (the left one makes the node, in its own
// place, the right one leaves), the list closes up, until `target` clusters or fewer are
// left. Some pair always chooses each other (as in PLOC's MarkMerges), so each step merges at
// least once and a list of c clusters takes at most c - target steps. `nodes` counts the new
// nodes and writes them: int reserve(int count) and
// void write(int node, int left, int right, const Aabb& box, int leaves, int leaves_left).
template <class Nodes>
void merge_cluster_list(ClusterList& list, int target, int radius, Nodes& nodes) {
  while (list.count > target) {
    int neighbour[k_warp_lanes];
    for (int lane = 0; lane < list.count; ++lane)
      neighbour[lane] = nearest_cluster(list, lane, radius);
    unsigned makes = 0, stays = 0;
    for (int lane = 0; lane < list.count; ++lane) {
      const int j = neighbour[lane];
      const bool mutual = j >= 0 && neighbour[j] == lane;
      makes |= unsigned(mutual && lane < j) << lane;
      stays |= unsigned(!(mutual && lane > j)) << lane;
    }
    const int first = nodes.reserve(count_bits(makes));
    for (int lane = 0; lane < list.count; ++lane) {
      if ((makes >> lane & 1u) == 0) continue;
      const int j = neighbour[lane];
      Aabb box = list.box[lane];
      box.grow(list.box[j]);
      const int node = first + count_bits(makes & lanes_below(lane));
      const int leaves = list.leaves[lane] + list.leaves[j];
      nodes.write(node, list.id[lane], list.id[j], box, leaves, list.leaves[lane]);
      list.id[lane] = node;
      list.box[lane] = box;
      list.leaves[lane] = leaves;
    }
    const int kept = count_bits(stays);
    for (int p = 0; p < kept; ++p) { // in order: a place never runs ahead of its source
      const int from = nth_set_bit(stays, p);
      list.id[p] = list.id[from];
      list.box[p] = list.box[from];
      list.leaves[p] = list.leaves[from];
    }
    list.count = kept;
  }
}

} // namespace rt::ch10
