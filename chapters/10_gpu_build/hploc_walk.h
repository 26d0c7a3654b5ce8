// Chapter 10: H-PLOC's walk up the LBVH (hploc.h has its pieces), written once for each way
// it runs: on CPU threads, a thread per leaf and a list merged with the lanes in a loop
// (walk_on_cpu), and on a warp, a lane per leaf and a list merged by all 32 lanes together
// (walk_on_warp). The warp's code takes its collective operations (votes, shuffles) from a
// Warp type: in the kernel the CUDA intrinsics (hploc.cu), in a test fibers on a CPU thread
// that play the 32 lanes in lockstep, so that the GPU's code is also tested where no GPU is.
#pragma once

#include <cstdint>

#include "hploc.h"
#include "refit.h" // load_published

namespace rt::ch10 {

// What the walk reads and writes.
struct HplocWalk {
  ClusterTree tree;
  const std::uint32_t* codes;   // sorted
  unsigned long long* far_ends; // n - 1: the first arrival's far_end_word, or k_no_far_end
  int* clusters;                // n: each subtree's list, from the start of its range
  int* node_counter;            // interior nodes made so far
  int radius, threshold;
  // The most clusters a completed subtree's list keeps: the threshold, one at the root.
  RT_HD int target(int first, int last) const {
    return first == 0 && last == tree.n - 1 ? 1 : threshold;
  }
};

// ---- CPU threads: a thread per leaf, the warp's lanes in a loop ----------------------------

// New nodes from the shared counter, written into the tree.
struct CpuNodes {
  const HplocWalk& walk;
  int reserve(int count) { return walk.tree.n + reserve_nodes(walk.node_counter, count); }
  void write(int node, int left, int right, const Aabb& box, int leaves, int leaves_left) {
    write_cluster_node(walk.tree, node, left, right, box, leaves, leaves_left);
  }
};

// The two children's lists side by side: the left child's from `first`, the right child's
// from `split`, each up to its first -1 or its slots_to_read.
inline ClusterList gather_lists(const HplocWalk& walk, int first, int split, int last) {
  ClusterList list;
  for (int side = 0; side < 2; ++side) {
    const int start = side == 0 ? first : split;
    const int slots =
        slots_to_read(side == 0 ? split - first : last - split + 1, walk.threshold);
    for (int k = 0; k < slots; ++k) {
      const int id = walk.clusters[start + k];
      if (id < 0) break;
      list.id[list.count] = id;
      list.box[list.count] = walk.tree.boxes[id];
      list.leaves[list.count] = walk.tree.leaf_counts[id];
      ++list.count;
    }
  }
  return list;
}

// The thread of one leaf, climbing while it arrives second.
inline void walk_on_cpu(const HplocWalk& walk, int leaf) {
  const int n = walk.tree.n;
  Climber s = start_climb(walk.codes, n, leaf);
  CpuNodes nodes{walk};
  while (climb(n, walk.far_ends, s)) {
    const int first = s.first, last = s.last;
    if (!gathers(first, last, n, walk.threshold)) continue;
    ClusterList list = gather_lists(walk, first, s.split, last);
    merge_cluster_list(list, walk.target(first, last), walk.radius, nodes);
    for (int k = 0; k < list.count; ++k) walk.clusters[first + k] = list.id[k];
    if (list.count < slots_to_read(last - first + 1, walk.threshold))
      walk.clusters[first + list.count] = -1;
    if (first == 0 && last == n - 1) return;
  }
}

// ---- A warp: a lane per leaf, a list merged by all 32 lanes --------------------------------
//
// A Warp gives the lane its collective operations; every lane of the warp must call each one,
// in the same order (on the GPU they are the _sync intrinsics over all 32 lanes):
//   unsigned ballot(bool)             the lanes whose argument is true, as a mask
//   bool any(bool)                    whether any lane's argument is true
//   int shfl(int, int from), float shfl(float, int from)   lane `from`'s value (from % 32)
//   float shfl_down(float, int d)     lane + d's value; the lane's own where lane + d > 31
//   float shfl_up(float, int d)       lane - d's value; the lane's own where lane - d < 0
//   void sync()                       the warp in step: what any lane did before it comes
//                                     before what every lane does after it
//   void publish()                    every lane's writes seen by any thread that sees an
//                                     exchange the warp makes after it (the warp in step,
//                                     then a fence)

// Reads of what another thread wrote during the walk, past the GPU's L1 cache (refit.h's
// load_published, and a box's the same way).
RT_HD inline Aabb load_published(const Aabb& box) {
  const volatile float* f = &box.lo.x;
  Aabb out;
  out.lo = {f[0], f[1], f[2]};
  out.hi = {f[3], f[4], f[5]};
  return out;
}

// The lowest set bit's place, or -1 for 0.
RT_HD inline int lowest_set_bit(unsigned x) {
#if RT_ON_DEVICE
  return __ffs(static_cast<int>(x)) - 1;
#else
  return __builtin_ffs(static_cast<int>(x)) - 1;
#endif
}

// A box from another lane, six shuffles.
template <class Warp> RT_HD Aabb shuffle_box(Warp& warp, const Aabb& box, int from) {
  Aabb out;
  out.lo = {warp.shfl(box.lo.x, from), warp.shfl(box.lo.y, from), warp.shfl(box.lo.z, from)};
  out.hi = {warp.shfl(box.hi.x, from), warp.shfl(box.hi.y, from), warp.shfl(box.hi.z, from)};
  return out;
}

// [listing:hploc_nearest_warp]
// nearest_cluster on the warp: the lane computes the cost of its merge with the lane d places
// to its right, whose box comes down by a shuffle, and hands the cost up to that lane by
// another, so each of the 2 * radius candidates costs one box shuffle per pair, not one per
// lane. The costs are merge_cost's, left box first, as on the CPU. The candidates come in by
// distance, so better_candidate's order needs no place comparison: every candidate met
// before lies less than d places away, so lane + d lies right of all of them and must be
// strictly cheaper, and lane - d lies left of all of them and wins a tie. Past count - 1
// places there is nobody: the loop stops there (count is the same on every lane).
template <class Warp>
RT_HD int nearest_on_warp(Warp& warp, int lane, int count, int radius, const Aabb& own) {
  int best = -1;
  float best_cost = std::numeric_limits<float>::infinity();
  const int reach = radius < count - 1 ? radius : count - 1;
  for (int d = 1; d <= reach; ++d) {
    Aabb right;
    right.lo = {warp.shfl_down(own.lo.x, d), warp.shfl_down(own.lo.y, d),
                warp.shfl_down(own.lo.z, d)};
    right.hi = {warp.shfl_down(own.hi.x, d), warp.shfl_down(own.hi.y, d),
                warp.shfl_down(own.hi.z, d)};
    const float cost = merge_cost(own, right);     // with lane + d, if it is in the list
    const float from_left = warp.shfl_up(cost, d); // lane - d's, with this lane
    if (lane + d < count && (best < 0 || cost < best_cost)) {
      best = lane + d;
      best_cost = cost;
    }
    if (lane < count && lane - d >= 0 && from_left <= best_cost) { // infinity <= infinity
      best = lane - d;
      best_cost = from_left;
    }
  }
  return best;
}
// [/listing:hploc_nearest_warp]

// [listing:hploc_merge_warp]
// The list of the subtree first..last, merged by the whole warp, one cluster per lane: lanes
// 0-15 read the left child's list, lanes 16-31 the right child's, a vote counts each, and
// shuffles close the gap. Then merge_cluster_list's steps, a lane each: the nearest
// neighbour through shuffles, the mutual pairs by a vote, one atomic for the warp's new
// nodes, and the list closed up by shuffles from the lanes that stay.
template <class Warp>
RT_HD void merge_on_warp(Warp& warp, const HplocWalk& walk, int lane, int first, int split,
                         int last) {
  warp.sync(); // the owner's exchange and fence come before every lane's reads
  const int half = lane / k_hploc_threshold, slot = lane % k_hploc_threshold;
  const int start = half == 0 ? first : split;
  const int size = half == 0 ? split - first : last - split + 1;
  int id = slot < slots_to_read(size, walk.threshold)
               ? load_published(&walk.clusters[start + slot])
               : -1;
  const unsigned missing = warp.ballot(id < 0);
  const int left_count = lowest_set_bit((missing & 0xffffu) | 0x10000u);
  const int right_count = lowest_set_bit((missing >> 16) | 0x10000u);
  int count = left_count + right_count;
  id = warp.shfl(id, lane < left_count ? lane : k_hploc_threshold + lane - left_count);
  Aabb box;
  int leaves = 0;
  if (lane < count) {
    box = load_published(walk.tree.boxes[id]);
    leaves = load_published(&walk.tree.leaf_counts[id]);
  }
  const int target = walk.target(first, last);
  while (count > target) {
    const int j = nearest_on_warp(warp, lane, count, walk.radius, box);
    const int back = warp.shfl(j, j < 0 ? lane : j);
    const bool mutual = lane < count && j >= 0 && back == lane;
    const unsigned makes = warp.ballot(mutual && lane < j);
    const unsigned stays = warp.ballot(lane < count && !(mutual && lane > j));
    int first_node = 0;
    if (lane == 0)
      first_node = walk.tree.n + reserve_nodes(walk.node_counter, count_bits(makes));
    first_node = warp.shfl(first_node, 0);
    const bool make = (makes >> lane & 1u) != 0;
    const int partner = make ? j : lane;
    const Aabb partner_box = shuffle_box(warp, box, partner);
    const int partner_id = warp.shfl(id, partner);
    const int partner_leaves = warp.shfl(leaves, partner);
    if (make) {
      box.grow(partner_box);
      const int node = first_node + count_bits(makes & lanes_below(lane));
      write_cluster_node(walk.tree, node, id, partner_id, box, leaves + partner_leaves, leaves);
      leaves += partner_leaves;
      id = node;
    }
    count = count_bits(stays);
    const int from = lane < count ? nth_set_bit(stays, lane) : lane;
    id = warp.shfl(id, from);
    box = shuffle_box(warp, box, from);
    leaves = warp.shfl(leaves, from);
  }
  if (lane < count) walk.clusters[first + lane] = id;
  if (lane == count && count < slots_to_read(last - first + 1, walk.threshold))
    walk.clusters[first + lane] = -1;
  warp.publish(); // every lane's nodes and list, seen before the owner's next exchange
}
// [/listing:hploc_merge_warp]

// [listing:hploc_kernel]
// The lane of one leaf (leaf >= n: a lane past the end, which only helps). Every lane stays
// in the loop until no lane of its warp climbs, because the merges need all 32; after each
// step up, the lanes whose subtree needs its list looked at are taken one at a time (a vote
// lists them), the warp merging each.
template <class Warp>
RT_HD void walk_on_warp(Warp& warp, const HplocWalk& walk, int leaf, int lane) {
  const int n = walk.tree.n;
  bool climbing = leaf < n;
  Climber s = climbing ? start_climb(walk.codes, n, leaf) : Climber{leaf, leaf, 0, -1, -1};
  while (warp.any(climbing)) {
    if (climbing) climbing = climb(n, walk.far_ends, s);
    unsigned waiting = warp.ballot(climbing && gathers(s.first, s.last, n, walk.threshold));
    while (waiting != 0) {
      const int owner = lowest_set_bit(waiting);
      waiting &= waiting - 1;
      merge_on_warp(warp, walk, lane, warp.shfl(s.first, owner), warp.shfl(s.split, owner),
                    warp.shfl(s.last, owner));
    }
    if (s.first == 0 && s.last == n - 1) climbing = false; // the root: done
  }
}
// [/listing:hploc_kernel]

} // namespace rt::ch10
