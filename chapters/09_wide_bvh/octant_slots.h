// Chapter 09: which octant slot each child of a wide node takes. A small function of the
// children's boxes alone, RT_HD so that chapter 10's parallel collapse, running on the GPU,
// assigns the slots exactly as chapter 09's collapse does on the CPU.
#pragma once

#include "bvh.h"
#include "rt/hd.h"
#include "rt/vec.h"
#include "wide_bvh.h"

namespace rt::ch09 {

// [listing:octant_slots]
// Slot s is meant for rays whose direction has the signs of octant s (bit 0: x negative, bit 1:
// y, bit 2: z): they should visit first the child whose centre lies furthest back along their
// direction. A child's cost in slot s is the offset of its centre from the node's centre,
// projected on the octant's diagonal; pairs are taken cheapest first (the first pair in child
// then slot order among equal costs), each child and each slot once (the paper's greedy
// assignment). Rays of octant o then visit slot o first, and the other slots in the order
// s ^ o = 1, 2, 3, ... (wide_traverse.h).
//
// The children sit at fixed places c < N, present where bit c of `present` is set; slot_of[c]
// receives the slot of each present child. Every loop has a fixed count and every array a
// fixed index once the loops are unrolled, and the taken children and slots are bit masks: on
// the GPU the whole assignment stays in registers (an array indexed by a number known only at
// run time would go to local memory, which in chapter 10's collapse cost more than the rest
// of it together).
template <int N>
RT_HD inline void assign_slots(const Aabb& node, const Aabb (&boxes)[N], unsigned present,
                               int (&slot_of)[N]) {
  static_assert(N <= k_slots);
  // Offsets doubled (lo + hi against the node's lo + hi): the same order, no halving. Float
  // sums of signed components, which every backend rounds alike: the slots do not depend on
  // where the collapse runs.
  const Vec3f twice_centre = node.lo + node.hi;
  Vec3f offset[N];
  RT_UNROLL
  for (int c = 0; c < N; ++c) {
    offset[c] = boxes[c].lo + boxes[c].hi - twice_centre;
    slot_of[c] = -1;
  }
  unsigned children_left = present, slots_free = (1u << k_slots) - 1u;
  while (children_left != 0) {
    int best_child = -1, best_slot = -1;
    float best_cost = 0.0f;
    RT_UNROLL
    for (int c = 0; c < N; ++c) {
      if ((children_left >> c & 1u) == 0) continue;
      RT_UNROLL
      for (int s = 0; s < k_slots; ++s) {
        const float cost = (s & 1 ? -offset[c].x : offset[c].x) +
                           (s & 2 ? -offset[c].y : offset[c].y) +
                           (s & 4 ? -offset[c].z : offset[c].z);
        if ((slots_free >> s & 1u) != 0 && (best_child < 0 || cost < best_cost)) {
          best_child = c;
          best_slot = s;
          best_cost = cost;
        }
      }
    }
    RT_UNROLL
    for (int c = 0; c < N; ++c)
      if (c == best_child) slot_of[c] = best_slot;
    children_left &= ~(1u << best_child);
    slots_free &= ~(1u << best_slot);
  }
}
// [/listing:octant_slots]

} // namespace rt::ch09
