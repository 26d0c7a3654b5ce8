// Chapter 13: the two-level walk. The top level is a binary tree over the instances' world
// boxes, in chapter 07's layout (chapter 10's LBVH over boxes builds it, every frame if the
// instances move); its leaves name instances. At a leaf the ray goes to the instance's own
// space and walks that mesh's bottom-level tree, chapter 09's 4-wide packed tree, built once
// per mesh however many instances place it. One RT_HD function for both backends and both
// queries.
#pragma once

#include <type_traits>

#include "bvh.h"
#include "instance.h"
#include "traverse.h"
#include "wide_bvh.h"
#include "wide_traverse.h"

namespace rt::ch13 {

using ch07::Query;
using BottomView = ch09::Wide4PackedBvh::View;

// [listing:two_level_view]
// A top-level leaf: an instance, and the node of its mesh's tree the walk below starts from:
// the root (0), or, where the instance is opened (instance_scene.h), the root of one of the
// subtrees that cover the mesh.
struct TopEntry {
  int instance;
  int node;
};

// What the walk reads (host pointers on the CPU, device pointers on the GPU).
struct TwoLevelView {
  const ch07::BvhNode* top_nodes = nullptr; // top_node_count nodes; node 0 is the root
  const int* top_leaf_ids = nullptr;        // leaf slot k of the top level holds entry ids[k]
  int top_node_count = 0;                   // 0: no instances
  const TopEntry* entries = nullptr;
  const Instance* instances = nullptr;
  const BottomView* meshes = nullptr; // each mesh's bottom-level tree, by Instance::mesh
  // The same top level collapsed to chapter 09's 4-wide node (leaves of one entry, whose
  // record's id is the entry), where the scene keeps one; node_count 0 where it does not.
  BottomView top_wide;
};
// [/listing:two_level_view]

// Top-level nodes and instances visited, and bottom-level nodes and triangles, per ray.
struct TwoLevelCounters {
  long long top_nodes = 0, instances = 0;
  ch07::Counters bottom;
  RT_HD void top_node() { ++top_nodes; }
  RT_HD void instance() { ++instances; }
};
struct NoTwoLevelCounters {
  ch07::NoCounters bottom;
  RT_HD void top_node() {}
  RT_HD void instance() {}
};

// [listing:visit_instance]
// A top-level leaf: the ray, in the instance's space, through the mesh's tree from the entry's
// node, with the nearest hit so far as its tmax, so that only a nearer hit comes back. True
// when an any-hit query is answered.
template <Query kQuery, class C>
RT_HD bool visit_instance(const TwoLevelView& scene, int entry, unsigned mask, RayF& ray,
                          InstanceHit& hit, C& counters) {
  const TopEntry e = scene.entries[entry];
  const Instance& instance = scene.instances[e.instance];
  if ((instance.mask & mask) == 0) return false;
  counters.instance();
  const ch07::TraceHit h = ch09::trace_wide<kQuery>(
      scene.meshes[instance.mesh], to_object_space(instance, ray), counters.bottom, e.node);
  if (h.triangle < 0) return false;
  hit = {h.t, e.instance, h.triangle, h.u, h.v};
  ray.tmax = h.t;
  return kQuery == Query::any;
}
// [/listing:visit_instance]

// [listing:trace_instances]
// The closest (or any) hit among all instances whose mask shares a bit with `mask`: chapter
// 07's walk of a binary tree (nearer child first, the other on the stack; the 30-bit LBVH's
// depth is proved below the stack's size in chapter 10) with an instance at every leaf.
template <Query kQuery, class C = NoTwoLevelCounters>
RT_HD InstanceHit trace_instances(const TwoLevelView& scene, RayF ray,
                                  unsigned mask = 0xffffffffu, C&& counters = C{}) {
  InstanceHit hit;
  if (scene.top_node_count == 0 || !ch07::traceable(ray)) return hit;
  const ch07::BoxRay box_ray = ch07::make_box_ray(ray);
  int stack[ch07::k_max_bvh_depth];
  int stack_size = 0;
  int node = 0;
  for (;;) {
    counters.top_node();
    const ch07::BvhNode n = scene.top_nodes[node];
    float t0 = 0.0f, t1 = 0.0f;
    bool enter0 = ch07::enter_box(n.box[0], box_ray, ray.tmin, ray.tmax, t0);
    bool enter1 = ch07::enter_box(n.box[1], box_ray, ray.tmin, ray.tmax, t1);
    if (enter0 && n.is_leaf(0)) {
      if (visit_instance<kQuery>(scene, scene.top_leaf_ids[n.first[0]], mask, ray, hit,
                                 counters))
        return hit;
      enter0 = false;
    }
    if (enter1 && n.is_leaf(1)) {
      if (visit_instance<kQuery>(scene, scene.top_leaf_ids[n.first[1]], mask, ray, hit,
                                 counters))
        return hit;
      enter1 = false;
    }
    if (enter0 && enter1) {
      const bool second_nearer = t1 < t0;
      stack[stack_size++] = second_nearer ? n.first[0] : n.first[1];
      node = second_nearer ? n.first[1] : n.first[0];
    } else if (enter0) {
      node = n.first[0];
    } else if (enter1) {
      node = n.first[1];
    } else if (stack_size > 0) {
      node = stack[--stack_size];
    } else {
      return hit;
    }
  }
}
// [/listing:trace_instances]

// [listing:wide_top]
// The top level as chapter 09's 4-wide tree, walked by chapter 09's own walk (trace_wide): its
// leaves' "triangles" are entries, and the test of one is the visit of an instance. The walk
// keeps what the test returns as it keeps a triangle's hit, t shortening the ray; the instance
// and the mesh's triangle go to `best`, which the walk's own hit cannot carry.
struct EntryRef {
  int entry;
};
struct TopWideView {
  BottomView tree;
  int node_count;
  const float* columns = nullptr; // the CPU's eight-triangle test has nothing to read here
  int column_stride = 0;
  RT_HD decltype(auto) node(int i) const { return tree.node(i); }
  RT_HD EntryRef triangle(int k) const { return {tree.triangle_id(k)}; }
  RT_HD int triangle_id(int k) const { return tree.triangle_id(k); }
};

template <Query kQuery, class C> struct EnterInstance {
  const TwoLevelView* scene;
  unsigned mask;
  InstanceHit* best;
  C* counters;
  RT_HD ch04::TriangleHitF operator()(const RayF& ray, EntryRef e) {
    RayF r = ray;
    InstanceHit hit;
    if (!visit_instance<kQuery>(*scene, e.entry, mask, r, hit, *counters) && hit.instance < 0)
      return {};
    *best = hit;
    return {true, hit.t, hit.u, hit.v};
  }
};

// Chapter 07's counters of the top-level walk, passed on as the two-level counts.
template <class C> struct TopCounters {
  C* counters;
  RT_HD void node() { counters->top_node(); }
  RT_HD void triangle() {}
  RT_HD void stack(int) {}
};

template <Query kQuery, class C = NoTwoLevelCounters>
RT_HD InstanceHit trace_instances_wide(const TwoLevelView& scene, RayF ray,
                                       unsigned mask = 0xffffffffu, C&& counters = C{}) {
  InstanceHit best;
  if (scene.top_wide.node_count == 0) return best;
  using Counters = std::remove_reference_t<C>;
  const TopWideView top{scene.top_wide, scene.top_wide.node_count};
  ch09::trace_wide<kQuery>(top, ray, TopCounters<Counters>{&counters},
                           EnterInstance<kQuery, Counters>{&scene, mask, &best, &counters});
  return best;
}
// [/listing:wide_top]

// Either top level, as chosen when the kernel is compiled.
enum class TopLayout { binary, wide };
template <Query kQuery, TopLayout kTop, class C = NoTwoLevelCounters>
RT_HD InstanceHit trace_two_level(const TwoLevelView& scene, const RayF& ray,
                                  unsigned mask = 0xffffffffu, C&& counters = C{}) {
  if constexpr (kTop == TopLayout::wide)
    return trace_instances_wide<kQuery>(scene, ray, mask, counters);
  else
    return trace_instances<kQuery>(scene, ray, mask, counters);
}

} // namespace rt::ch13
