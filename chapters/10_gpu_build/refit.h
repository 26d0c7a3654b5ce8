// Chapter 10: boxes from the bottom up, for any tree in chapter 07's layout. Every node starts
// a thread; a thread boxes its node's leaf children, and whichever thread completes a node (the
// second of its two children to be boxed) boxes it and goes on to its parent. The same pass
// gives a freshly built tree its boxes and refits an old one to moved vertices, and boxes a
// tree whose leaves hold boxes rather than triangles.
#pragma once

#include "bvh.h"
#include "rt/hd.h"
#include "triangles.h"

namespace rt::ch10 {

using ch04::TriangleF;
using ch07::Aabb;
using ch07::BvhNode;

// [listing:arrive]
// One child of a node is boxed: true for the second of the two. On the GPU the fence before
// the atomic makes this thread's box visible to every other thread before its arrival counts,
// and the fence after it orders the sibling's box, read next, after the arrival. On CPU
// threads an acquire-release add says the same.
RT_HD inline bool second_arrival(unsigned* counter) {
#if RT_ON_DEVICE
  __threadfence();
  const unsigned before = atomicAdd(counter, 1u);
  __threadfence();
#else
  const unsigned before = __atomic_fetch_add(counter, 1u, __ATOMIC_ACQ_REL);
#endif
  return before == 1u;
}
// [/listing:arrive]

// What another thread wrote and published (second_arrival), read past the GPU's L1 cache,
// which another multiprocessor's writes do not reach: volatile loads go to L2.
RT_HD inline int load_published(const int* p) { return *static_cast<const volatile int*>(p); }
RT_HD inline double load_published(const double* p) {
  return *static_cast<const volatile double*>(p);
}

// A child box written by another thread, read past the GPU's L1 cache the same way.
RT_HD inline Aabb load_child_box(const BvhNode& node, int c) {
  const volatile float* f = &node.box[c].lo.x;
  Aabb box;
  box.lo = {f[0], f[1], f[2]};
  box.hi = {f[3], f[4], f[5]};
  return box;
}

// [listing:leaves]
// The box of a leaf child, the run of `count` leaf slots from `first`. A tree of triangles
// holds their copies in leaf order; a tree of boxes (chapter 13's instances) holds in slot k
// the number of a box the caller keeps. One box grown from the empty box is that box, bit for
// bit, so both kinds of tree get the same boxes from the same triangles.
struct TriangleLeaves {
  const TriangleF* triangles; // in leaf order
  RT_HD Aabb box(int first, int count) const {
    Aabb box;
    for (int k = first; k < first + count; ++k) box.grow(ch07::bounds_of(triangles[k]));
    return box;
  }
};
struct BoxLeaves {
  const Aabb* boxes; // the caller's, in its own order
  const int* ids;    // slot k holds boxes[ids[k]]
  RT_HD Aabb box(int first, int count) const {
    Aabb box;
    for (int k = first; k < first + count; ++k) box.grow(boxes[ids[k]]);
    return box;
  }
};
// [/listing:leaves]

// What the pass reads and writes: the nodes (boxes written), each node's parent as
// 2 * parent + child slot (-1 for the root), one arrival counter per node (zero at the start)
// and what boxes the leaves.
template <class Leaves> struct RefitView {
  BvhNode* nodes;
  const int* parents;
  unsigned* arrivals;
  Leaves leaves;
};

// [listing:refit_node]
// The thread of node i. Boxes are unions of boxes (min and max round nothing), so the order in
// which threads arrive changes no bit of the result: every backend makes the same tree.
template <class Leaves> RT_HD inline void refit_node(const RefitView<Leaves>& tree, int i) {
  for (int c = 0; c < 2; ++c) {
    const BvhNode& node = tree.nodes[i];
    if (!node.is_leaf(c)) continue;
    tree.nodes[i].box[c] = tree.leaves.box(node.first[c], node.count[c]);
    if (!second_arrival(&tree.arrivals[i])) continue;
    // This thread completed node i: climb while it keeps completing nodes.
    for (int x = i; tree.parents[x] >= 0;) {
      Aabb whole = load_child_box(tree.nodes[x], 0);
      whole.grow(load_child_box(tree.nodes[x], 1));
      const int parent = tree.parents[x] >> 1, slot = tree.parents[x] & 1;
      tree.nodes[parent].box[slot] = whole;
      if (!second_arrival(&tree.arrivals[parent])) break;
      x = parent;
    }
  }
}
// [/listing:refit_node]

} // namespace rt::ch10
