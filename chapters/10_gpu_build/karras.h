// Chapter 10: the hierarchy over sorted Morton codes (Karras 2012, "Maximizing Parallelism in
// the Construction of BVHs, Octrees, and k-d Trees"). Every interior node finds its own range
// of leaves and its split from the codes alone, so all n - 1 of them are made at once, one
// thread each, with no node waiting for its parent.
#pragma once

#include <cstdint>

#include "rt/hd.h"

namespace rt::ch10 {

// Leading zero bits of a word (x != 0), on either backend.
RT_HD inline int leading_zeros(std::uint32_t x) {
#if RT_ON_DEVICE
  return __clz(static_cast<int>(x));
#else
  return __builtin_clz(x);
#endif
}
RT_HD inline int leading_zeros(std::uint64_t x) {
#if RT_ON_DEVICE
  return __clzll(static_cast<long long>(x));
#else
  return __builtin_clzll(x);
#endif
}

// [listing:karras_delta]
// delta(i, j): the length of the common prefix of the keys of sorted leaves i and j, -1 when
// j lies outside 0 .. n-1. The key is the code followed by the leaf's own index, so no two
// keys are equal: where two codes are equal the prefix runs on into the index bits, and a run
// of equal codes is split like the binary numbers of its indices, evenly. Every code-prefix
// length is below the code word's width, every index-prefix length at least that width, so
// the two parts never mix.
template <class Code> RT_HD inline int delta(const Code* codes, int n, int i, long long j) {
  if (j < 0 || j >= n) return -1;
  const Code a = codes[i], b = codes[j];
  if (a != b) return leading_zeros(static_cast<Code>(a ^ b));
  return static_cast<int>(8 * sizeof(Code)) +
         leading_zeros(static_cast<std::uint32_t>(i) ^ static_cast<std::uint32_t>(j));
}
// [/listing:karras_delta]

// One interior node of the Karras tree: the leaves it covers, first..last, and its children.
// Child c is leaf number child[c] when is_leaf[c], else interior node number child[c].
struct KarrasNode {
  int first = 0, last = 0;
  int child[2] = {0, 0};
  bool is_leaf[2] = {false, false};
};

// [listing:karras_node]
// Interior node i of the tree over n >= 2 sorted codes. Node i always has leaf i at one end of
// its range; the other end lies in the direction d whose neighbour shares the longer prefix.
//  1. The range: every leaf of it shares more than delta_min = delta(i, i - d) bits with i.
//     Double a step until it leaves that prefix, then binary-search the last leaf inside.
//  2. The split: the last leaf, going from i towards the far end, that still shares more than
//     the node's own prefix delta(i, j) with i: found by another binary search.
// Leaves split..(split + 1) separate the two children; a child covering one leaf is that leaf.
template <class Code> RT_HD inline KarrasNode karras_node(const Code* codes, int n, int i) {
  const int d = delta(codes, n, i, i + 1LL) - delta(codes, n, i, i - 1LL) >= 0 ? 1 : -1;
  const int delta_min = delta(codes, n, i, static_cast<long long>(i) - d);
  long long step_max = 2;
  while (delta(codes, n, i, i + step_max * d) > delta_min) step_max *= 2;
  long long length = 0;
  for (long long t = step_max / 2; t >= 1; t /= 2)
    if (delta(codes, n, i, i + (length + t) * d) > delta_min) length += t;
  const long long j = i + length * d;
  const int delta_node = delta(codes, n, i, j);
  long long s = 0;
  for (long long divisor = 2;; divisor *= 2) {
    const long long t = (length + divisor - 1) / divisor;
    if (delta(codes, n, i, i + (s + t) * d) > delta_node) s += t;
    if (t <= 1) break;
  }
  const int split = static_cast<int>(i + s * d + (d < 0 ? -1 : 0));
  KarrasNode node;
  node.first = static_cast<int>(d > 0 ? i : j);
  node.last = static_cast<int>(d > 0 ? j : i);
  node.child[0] = split;
  node.child[1] = split + 1;
  node.is_leaf[0] = node.first == split;
  node.is_leaf[1] = node.last == split + 1;
  return node;
}
// [/listing:karras_node]

} // namespace rt::ch10
