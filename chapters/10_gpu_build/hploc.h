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

// What merging two clusters costs: the half area of their union, the left one's box grown by
// the right one's, the same operations in the same order on every backend. A NaN (an area of
// inf * 0, on coordinates near the float range's end) counts as infinity, so that the costs
// are totally ordered and a choice depends on nothing but them.
RT_HD inline float merge_cost(const Aabb& left, const Aabb& right) {
  Aabb merged = left;
  merged.grow(right);
  const float area = merged.half_area();
  return area <= std::numeric_limits<float>::max() ? area
                                                   : std::numeric_limits<float>::infinity();
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

// Interior node `node` (a number from n on) made of clusters left and right.
RT_HD inline void write_cluster_node(const ClusterTree& tree, int node, int left, int right,
                                     const Aabb& box, int leaves) {
  const int interior = node - tree.n;
  tree.nodes[interior] = {{left, right}};
  tree.boxes[node] = box;
  tree.leaf_counts[node] = leaves;
  tree.parents[left] = 2 * interior;
  tree.parents[right] = 2 * interior + 1;
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
// One step up the LBVH's hierarchy (Apetrei 2014) for the subtree over sorted leaves L..R.
// Its parent is the node of the boundary, L-1|L or R|R+1, whose two keys share the longer
// prefix (karras.h's delta): that boundary splits lower in the tree. The first of the
// parent's two children to arrive leaves its far end in the parent's slot and stops; the
// second takes it, and goes on with the parent's whole range and the place where its right
// child starts. The fences publish this subtree's clusters before the exchange, and order the
// sibling's, read next, after it (as second_arrival does for the refit).
RT_HD inline bool climb(const std::uint32_t* codes, int n, int* far_ends, int& first, int& last,
                        int& split) {
  const bool left_child =
      first == 0 || (last != n - 1 &&
                     delta(codes, n, last, last + 1LL) > delta(codes, n, first, first - 1LL));
  const int parent = left_child ? last : first - 1;
  const int far_end = left_child ? first : last;
#if RT_ON_DEVICE
  __threadfence();
  const int other = atomicExch(&far_ends[parent], far_end);
  __threadfence();
#else
  const int other = __atomic_exchange_n(&far_ends[parent], far_end, __ATOMIC_ACQ_REL);
#endif
  if (other < 0) return false;
  split = left_child ? last + 1 : first;
  (left_child ? last : first) = other;
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
// void write(int node, int left, int right, const Aabb& box, int leaves).
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
      nodes.write(node, list.id[lane], list.id[j], box, leaves);
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
