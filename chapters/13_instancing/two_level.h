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

// [listing:one_loop]
// Both levels in one loop. The walks above nest: at an instance the top level's loop stops and
// the mesh's runs to its end. On the GPU the 32 rays of a warp run as one, so while some of
// them are inside a dragon the others, still in the top level, wait for them; and the walk of
// a warp is as long as the sum of its rays' two walks. Here there is one loop: the top level
// is a 4-wide packed tree like the meshes' own, so a step is one node read whichever level the
// ray is in, and a warp's rays step together, some at the top and some below.
//   - A top-level node read gives entries where a mesh's gives triangles. They wait in
//     `entries` (the first slot of their leaves in the top's record array, and their bits) and
//     are entered one by one.
//   - To enter one, the top's node group and then a marker holding the entries still waiting
//     are pushed, and the ray, the tree and the group become the instance's.
//   - When the instance's walk empties its groups, the pop finds the marker: the ray, the tree
//     and the waiting entries become the top's again, the nearest hit's t kept (t is the same
//     in both spaces, the direction not being normalised).
// A marker is told from a node group by its base, which is negative (the bitwise complement
// of the entries' first slot). The stack holds the top's groups, one marker and the mesh's
// groups: at most two trees' depths and one.
struct TwoLevelStack {
  ch09::NodeGroup entries[2 * ch09::k_wide_stack_size + 1];
  RT_HD void store(int entry, ch09::NodeGroup group) { entries[entry] = group; }
  RT_HD ch09::NodeGroup load(int entry) const { return entries[entry]; }
};

template <Query kQuery, class C = NoTwoLevelCounters>
RT_HD InstanceHit trace_instances_one_loop(const TwoLevelView& scene, const RayF& world,
                                           unsigned mask = 0xffffffffu, C&& counters = C{}) {
  using ch09::NodeGroup;
  InstanceHit best;
  if (scene.top_wide.node_count == 0 || !ch07::traceable(world)) return best;
  RayF ray = world; // the level's ray: the world's at the top, the instance's below
  auto r = ch09::make_traversal_ray(ray);
  ch09::WatertightTest intersect(ray);
  BottomView tree = scene.top_wide;
  int instance = -1; // the instance being walked; -1 at the top
  int entries_base = 0;
  unsigned entries = 0; // entries waiting at the top, their bits counted from entries_base
  TwoLevelStack stack;
  int stack_size = 0;
  NodeGroup group{0, (1u << (24 + r.octant_inverse)) | 1u};
  for (;;) {
    // Every trip reads one node. Where nothing is left to read here, the stack says where
    // to go; the marker sends the ray back to the top, to the entries that still wait.
    while ((group.hits & ch09::k_child_bits) == 0 && entries == 0) {
      if (stack_size == 0) return best;
      group = stack.load(--stack_size);
      if (group.base < 0) {
        const float tmax = ray.tmax;
        ray = world;
        ray.tmax = tmax;
        r = ch09::make_traversal_ray(ray);
        tree = scene.top_wide;
        instance = -1;
        entries_base = ~group.base;
        entries = group.hits;
        group = {0, 0u};
      }
    }
    if (entries != 0) { // into the next waiting entry's instance; its root is the node read
      const int slot = entries_base + ch09::lowest_bit(entries);
      entries &= entries - 1;
      const TopEntry e = scene.entries[scene.top_wide.triangle_id(slot)];
      const Instance& placed = scene.instances[e.instance];
      if ((placed.mask & mask) == 0) continue;
      counters.instance();
      if (group.hits & ch09::k_child_bits) stack.store(stack_size++, group);
      stack.store(stack_size++, NodeGroup{~entries_base, entries});
      entries = 0;
      instance = e.instance;
      tree = scene.meshes[placed.mesh];
      ray = to_object_space(placed, ray); // ray is the world's here, its tmax the nearest hit
      r = ch09::make_traversal_ray(ray);
      intersect = ch09::WatertightTest(ray);
      group = {e.node, (1u << (24 + r.octant_inverse)) | 1u};
    }
    // chapter 09's step: the group's next child read, the rest of the group pushed
    const int bit = ch09::highest_bit(group.hits);
    group.hits &= ~(1u << bit);
    const unsigned slot = unsigned(bit - 24) ^ r.octant_inverse;
    const int node = group.base + ch09::bit_count(group.hits & ((1u << slot) - 1u) & 0xffu);
    if (group.hits & ch09::k_child_bits) stack.store(stack_size++, group);
    instance < 0 ? counters.top_node() : counters.bottom.node();
    const ch09::NodeHits h = ch09::intersect_node(tree.node(node), r, ray.tmin, ray.tmax);
    group = {h.child_base, h.children};
    if (instance < 0) { // entries wait; the next trip enters the first
      entries_base = h.triangle_base;
      entries = h.triangles;
      continue;
    }
    ch07::TraceHit hit;
    const bool answered = ch09::test_node_triangles<kQuery>(
        tree, h.triangle_base, h.triangles, ray, hit, counters.bottom, intersect);
    if (hit.triangle >= 0) best = {hit.t, instance, hit.triangle, hit.u, hit.v};
    if (answered) return best;
  }
}
// [/listing:one_loop]

// Which top level and walk, as chosen when the kernel is compiled:
//   - binary: chapter 07's node and walk at the top, chapter 09's walk called at each instance;
//   - nested: chapter 09's 4-wide packed node at the top, chapter 09's own walk at both levels,
//     the one at the top calling the one below at each instance;
//   - wide: the same trees, both levels in one loop (the default).
enum class TopLayout { binary, nested, wide };
template <Query kQuery, TopLayout kTop, class C = NoTwoLevelCounters>
RT_HD InstanceHit trace_two_level(const TwoLevelView& scene, const RayF& ray,
                                  unsigned mask = 0xffffffffu, C&& counters = C{}) {
  if constexpr (kTop == TopLayout::wide)
    return trace_instances_one_loop<kQuery>(scene, ray, mask, counters);
  else if constexpr (kTop == TopLayout::nested)
    return trace_instances_wide<kQuery>(scene, ray, mask, counters);
  else
    return trace_instances<kQuery>(scene, ray, mask, counters);
}

// Calls f with the layout as a compile-time constant (std::integral_constant), so that the
// kernel f launches is compiled for that walk.
template <class F> void with_top_layout(TopLayout top, F&& f) {
  using L = TopLayout;
  if (top == L::wide)
    f(std::integral_constant<L, L::wide>{});
  else if (top == L::nested)
    f(std::integral_constant<L, L::nested>{});
  else
    f(std::integral_constant<L, L::binary>{});
}

} // namespace rt::ch13
