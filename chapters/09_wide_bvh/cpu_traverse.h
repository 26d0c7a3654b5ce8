// Chapter 09: walking the CPU's own tree (cpu_tree.h). Host code only. Each node read tests
// the ray against the eight child boxes at once, as wide_traverse.h does, keeps their entry
// distances, tests the triangles of the leaves entered, and goes on to the nearest interior
// child entered; the others wait on a stack with their distances.
#pragma once

#include <bit>
#include <utility>

#include "cpu_tree.h"
#include "wide_traverse.h"

namespace rt::ch09 {

// A child waiting on the stack: its node and the distance at which the ray enters its box.
struct CpuStackEntry {
  int node;
  float t_enter;
};

// [listing:cpu_stack_bound]
// A node read pushes at most 7 children (8 entered, one visited at once), and they are all
// popped before anything pushed earlier. So the stack holds at most 7 entries per level of
// the tree above the node being read: 7 times the wide stack's bound (wide_bvh.h), which
// covers the deepest tree chapter 07's build may make.
inline constexpr int k_cpu_stack_size = (k_slots - 1) * k_wide_stack_size;
// [/listing:cpu_stack_bound]

// What one node read yields: the interior children entered (bit c: child c), the triangles
// of the leaves entered (bits of the node's triangle block) and every child's entry distance.
struct CpuNodeRead {
  unsigned interior;
  unsigned triangles;
  alignas(32) float t_enter[k_slots];
};

// The read with no vector instructions written out: chapter 07's slab test, child by child,
// through enter_children_cpu (which the compiler vectorises).
inline CpuNodeRead read_cpu_node(const CpuNode& n, const WideRay& r, float tmin, float tmax) {
  CpuNodeRead read{0u, 0u, {}};
  const unsigned entered = enter_children_cpu(n.lo_x, n.lo_y, n.lo_z, n.hi_x, n.hi_y, n.hi_z,
                                              r.box, tmin, tmax, read.t_enter);
  for (unsigned left = entered; left != 0; left &= left - 1) {
    const int c = std::countr_zero(left);
    if (is_cpu_leaf(n.child[c]))
      read.triangles |= cpu_leaf_triangles(n.child[c]);
    else
      read.interior |= 1u << c;
  }
  return read;
}

#if defined(__AVX2__)
// [listing:cpu_node_avx2]
// With AVX2 the same read in eight lanes: enter_eight's slab test (the same arithmetic), then
// the child words split by their sign, the flag of a leaf, all in registers: the interior
// children entered are one movemask, the leaves' triangle bits one AND and an OR across lanes.
RT_INLINE_ON_CPU inline CpuNodeRead read_cpu_node(const CpuNode& n, const WideRayAvx2& r,
                                                  float tmin, float tmax) {
  CpuNodeRead read;
  __m256 t_enter;
  const __m256 entered = enter_eight(&n, r.lanes, tmin, tmax, t_enter);
  _mm256_store_ps(read.t_enter, t_enter);
  const __m256i child = _mm256_load_si256(reinterpret_cast<const __m256i*>(n.child));
  const __m256 leaf = _mm256_castsi256_ps(_mm256_srai_epi32(child, 31)); // all ones: a leaf
  read.interior = unsigned(_mm256_movemask_ps(_mm256_andnot_ps(leaf, entered)));
  const __m256i bits =
      _mm256_and_si256(_mm256_and_si256(child, _mm256_set1_epi32(int(k_cpu_leaf_bits))),
                       _mm256_castps_si256(_mm256_and_ps(leaf, entered)));
  __m128i x = _mm_or_si128(_mm256_castsi256_si128(bits), _mm256_extracti128_si256(bits, 1));
  x = _mm_or_si128(x, _mm_unpackhi_epi64(x, x));
  x = _mm_or_si128(x, _mm_shuffle_epi32(x, 1));
  read.triangles = unsigned(_mm_cvtsi128_si32(x));
  return read;
}
// [/listing:cpu_node_avx2]
#endif

// [listing:cpu_traverse]
// The closest (or any) hit of `ray` among the tree's triangles: the same as trace_wide's on
// the wide tree of the same collapse, up to which of two triangles at exactly the same
// distance is kept.
//
// A node read first tests the triangles of the leaves it entered, so that a hit there shortens
// the ray before any child is chosen. Then, for a closest hit, the interior children that the
// ray now enters beyond its end are dropped. One child left: it is read next, with no stack
// traffic. Several: all go on the stack, sorted so that the nearest is on top, and the top is
// read next. A popped child whose entry distance lies beyond the ray's end (a nearer hit was
// found since it was pushed) is dropped unread. That comparison is exactly the box test's own
// (t_enter <= tmax with chapter 07's slack), made with today's tmax, so it refuses no box that
// a fresh test would enter: the robustness argument of enter_children carries over. An any-hit
// query keeps the same order and stops at the first hit.
template <Query kQuery, class C, class Test>
RT_INLINE_ON_CPU inline TraceHit trace_cpu(const CpuTreeView& tree, RayF ray, C&& counters,
                                           Test intersect) {
  TraceHit hit;
  if (tree.node_count == 0 || !ch07::traceable(ray)) return hit;
  const auto r = make_traversal_ray(ray);
  CpuStackEntry stack[k_cpu_stack_size];
  int size = 0;
  int node = 0;
  for (;;) {
    counters.node();
    const CpuNode& n = tree.node(node);
    const CpuNodeRead read = read_cpu_node(n, r, ray.tmin, ray.tmax);
    if (read.triangles != 0 &&
        test_node_triangles<kQuery>(tree, n.triangle_base, read.triangles, ray, hit, counters,
                                    intersect))
      return hit; // an any-hit query is answered
    unsigned children = read.interior;
    if (kQuery == Query::closest && hit.triangle >= 0) {
      const float reach = ray.tmax * ch07::k_tmax_slack;
      for (unsigned left = children; left != 0; left &= left - 1)
        if (read.t_enter[std::countr_zero(left)] > reach)
          children &= ~(1u << std::countr_zero(left));
    }
    if (children != 0) {
      const int first = std::countr_zero(children);
      children &= children - 1;
      if (children == 0) { // one child: straight to it
        node = n.child[first];
        continue;
      }
      // Several: the farther ones onto the stack, the nearest on top of them taken at once.
      // Two, the common case, take one comparison; more are sorted in registers first.
      CpuStackEntry entries[k_slots];
      int count = 0;
      for (unsigned left = children | (1u << first); left != 0; left &= left - 1) {
        const int c = std::countr_zero(left);
        entries[count++] = {n.child[c], read.t_enter[c]};
      }
      if (count == 2) {
        const bool swap = entries[0].t_enter < entries[1].t_enter;
        stack[size++] = entries[swap ? 1 : 0];
        node = entries[swap ? 0 : 1].node;
        counters.stack(size);
        continue;
      }
      for (int i = 1; i < count; ++i) // farthest first
        for (int j = i; j > 0 && entries[j - 1].t_enter < entries[j].t_enter; --j)
          std::swap(entries[j - 1], entries[j]);
      for (int i = 0; i < count - 1; ++i) stack[size++] = entries[i];
      node = entries[count - 1].node;
      counters.stack(size);
      continue;
    }
    for (;;) { // nothing entered here: the nearest waiting child still within reach
      if (size == 0) return hit;
      const CpuStackEntry entry = stack[--size];
      if (kQuery == Query::any || entry.t_enter <= ray.tmax * ch07::k_tmax_slack) {
        node = entry.node;
        break;
      }
    }
  }
}
// [/listing:cpu_traverse]

template <Query kQuery, class C = ch07::NoCounters>
TraceHit trace_cpu(const CpuTreeView& tree, const RayF& ray, C&& counters = C{}) {
  return trace_cpu<kQuery>(tree, ray, counters, WatertightTest(ray));
}

} // namespace rt::ch09
