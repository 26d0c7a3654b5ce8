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
// s ^ o = 1, 2, 3, ... (wide_traverse.h). slot_of[c] receives child c's slot, c < count <= 8.
RT_HD inline void assign_slots(const Aabb& node, const Aabb* boxes, int count, int* slot_of) {
  // Offsets doubled (lo + hi against the node's lo + hi): the same order, no halving. Float
  // sums of signed components, which every backend rounds alike: the slots do not depend on
  // where the collapse runs.
  const Vec3f twice_centre = node.lo + node.hi;
  float cost[k_slots][k_slots];
  for (int c = 0; c < count; ++c) {
    const Vec3f offset = boxes[c].lo + boxes[c].hi - twice_centre;
    for (int s = 0; s < k_slots; ++s)
      cost[c][s] = (s & 1 ? -offset.x : offset.x) + (s & 2 ? -offset.y : offset.y) +
                   (s & 4 ? -offset.z : offset.z);
    slot_of[c] = -1;
  }
  bool slot_taken[k_slots] = {};
  for (int pick = 0; pick < count; ++pick) {
    int best_child = -1, best_slot = -1;
    for (int c = 0; c < count; ++c) {
      if (slot_of[c] >= 0) continue;
      for (int s = 0; s < k_slots; ++s)
        if (!slot_taken[s] && (best_child < 0 || cost[c][s] < cost[best_child][best_slot]))
          best_child = c, best_slot = s;
    }
    slot_of[best_child] = best_slot;
    slot_taken[best_slot] = true;
  }
}
// [/listing:octant_slots]

} // namespace rt::ch09
