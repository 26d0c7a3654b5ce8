// Chapter 07: walking the tree. One RT_HD function serves both backends and both questions a
// renderer asks: the closest hit (camera rays, bounces) and any hit (shadow rays, ambient
// occlusion). It visits only the nodes whose boxes the ray enters, nearer child first, so a
// ray costs about log N box tests and a few triangle tests instead of N triangle tests.
#pragma once

#include <cmath>
#include <limits>

#include "bvh.h"
#include "triangles.h"

namespace rt::ch07 {

using ch03::RayF;
using ch04::MeshHit;
using ch04::TriangleVariant;

enum class Query { closest, any };

const char* to_string(Query query);

// The closest (or any) hit, with the barycentrics shading needs; triangle is the mesh's own
// number. t = +inf, triangle = -1 for a miss.
struct TraceHit {
  float t = std::numeric_limits<float>::infinity();
  int triangle = -1;
  float u = 0.0f, v = 0.0f;
};

// Whether a ray can be traced at all. NaN or infinity in the origin or direction, a zero
// direction or NaN bounds would send NaN through every box test: such a ray misses at once,
// before the traversal touches the tree.
RT_INLINE_ON_CPU RT_HD inline bool traceable(const RayF& ray) {
  const Vec3f o = ray.origin, d = ray.direction;
  const bool finite = ch04::is_finite(o.x) && ch04::is_finite(o.y) && ch04::is_finite(o.z) &&
                      ch04::is_finite(d.x) && ch04::is_finite(d.y) && ch04::is_finite(d.z);
  const bool has_direction = d.x != 0.0f || d.y != 0.0f || d.z != 0.0f;
  return finite && has_direction && ray.tmin == ray.tmin && ray.tmax == ray.tmax;
}

// [listing:box_ray]
// What every box test of one ray shares, computed once per ray. 1/d is +-infinity for a zero
// component (IEEE division by a signed zero), which is what the slab test below needs. The
// sign of 1/d, not d < 0, chooses the near plane: -0.0 has the reciprocal -inf, so it must
// pick the planes of a negative direction. Chosen by d < 0, every box whose slab on that axis
// contains the origin (the only boxes such a ray can enter) gets an empty interval.
struct BoxRay {
  Vec3f origin;
  Vec3f inverse; // 1 / direction, per component
  bool negative[3];
};

RT_HD inline BoxRay make_box_ray(const RayF& ray) {
  const Vec3f d = ray.direction;
  const Vec3f inverse{1.0f / d.x, 1.0f / d.y, 1.0f / d.z};
  return {ray.origin, inverse, {inverse.x < 0.0f, inverse.y < 0.0f, inverse.z < 0.0f}};
}
// [/listing:box_ray]

// The larger and the smaller of two floats where a NaN argument loses: the other one is
// returned (fmaxf's and fminf's rule, which the slab test below relies on). On the GPU these
// are fmaxf and fminf, one FMNMX instruction each. x86-64 has no instruction with that rule
// (maxss returns its second operand when either is NaN), so there the C library's fmaxf and
// fminf are function calls, a fifth of the CPU traversal's instructions (callgrind); written
// out, the compiler makes compares and selects of them.
RT_HD inline float max_ignoring_nan(float a, float b) {
#if defined(__CUDA_ARCH__)
  return fmaxf(a, b);
#else
  return (a > b || b != b) ? a : b;
#endif
}
RT_HD inline float min_ignoring_nan(float a, float b) {
#if defined(__CUDA_ARCH__)
  return fminf(a, b);
#else
  return (a < b || b != b) ? a : b;
#endif
}

// 2^-16 of the distance, far more than the few float steps (2^-24 each) that the watertight
// test's t is short by for a triangle not crossing the plane through the ray's origin; the
// boxes it keeps that end up empty cost nothing measurable.
inline constexpr float k_tmax_slack = 1.0f + 0x1p-16f;

// [listing:slab_test]
// The slab test: the ray is inside the box where it is inside all three pairs of planes.
// Each axis gives the distances to its near and far plane; the ray enters the box at the
// largest near distance and leaves at the smallest far one.
//   - A zero direction component with the origin exactly on a plane makes 0 * inf = NaN.
//     max/min_ignoring_nan return the other argument when one is NaN, so that axis stops
//     constraining the ray: an origin on the boundary counts as inside, the conservative
//     answer. With the origin strictly outside that slab, the distance is +-inf and the
//     box is missed, as it must be.
//   - Each distance (b - o) * (1/d) takes three rounded operations (the reciprocal, the
//     difference, the product), so it may be off by gamma(3) of itself, where
//     gamma(n) = n u / (1 - n u) and u = 2^-24. The entry may come out that much too late and
//     the exit that much too early: the exit is enlarged by 2 gamma(3) (Ize 2013, "Robust
//     BVH Ray Traversal"), so a ray that touches a box in exact arithmetic is never refused.
//   - The box is compared with tmax, the nearest hit so far, enlarged by k_tmax_slack: the
//     triangle test rounds too, and its t can come out a few float steps short of the exact
//     distance, so a triangle whose computed t lies below tmax can sit in a box whose computed
//     entry lies just past it. Compared with tmax itself, the tree could skip the float-nearest
//     of two triangles a float step apart and keep the other, where brute force keeps the
//     nearer (1 ray in 2 million of the conference room's diffuse rays did).
// The box is entered where t_enter <= t_exit; t_enter is returned to order the children.
RT_HD inline bool enter_box(const Aabb& box, const BoxRay& r, float tmin, float tmax,
                            float& t_enter) {
  constexpr float k_widen = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);
  const float near_x = ((r.negative[0] ? box.hi.x : box.lo.x) - r.origin.x) * r.inverse.x;
  const float near_y = ((r.negative[1] ? box.hi.y : box.lo.y) - r.origin.y) * r.inverse.y;
  const float near_z = ((r.negative[2] ? box.hi.z : box.lo.z) - r.origin.z) * r.inverse.z;
  const float far_x = ((r.negative[0] ? box.lo.x : box.hi.x) - r.origin.x) * r.inverse.x;
  const float far_y = ((r.negative[1] ? box.lo.y : box.hi.y) - r.origin.y) * r.inverse.y;
  const float far_z = ((r.negative[2] ? box.lo.z : box.hi.z) - r.origin.z) * r.inverse.z;
  t_enter = max_ignoring_nan(max_ignoring_nan(near_x, near_y), max_ignoring_nan(near_z, tmin));
  const float t_exit = min_ignoring_nan(min_ignoring_nan(far_x, far_y), far_z) * k_widen;
  return t_enter <= min_ignoring_nan(t_exit, tmax * k_tmax_slack);
}
// [/listing:slab_test]

// Counters for the report and the tests: free when not asked for (NoCounters compiles away).
struct NoCounters {
  RT_HD void node() {}
  RT_HD void triangle() {}
  RT_HD void stack(int) {}
};
struct Counters {
  int nodes = 0;     // interior nodes visited
  int triangles = 0; // triangle tests
  int max_stack = 0; // deepest the stack went
  RT_HD void node() { ++nodes; }
  RT_HD void triangle() { ++triangles; }
  RT_HD void stack(int size) { max_stack = size > max_stack ? size : max_stack; }
};

// The triangles of one leaf against the ray; tmax shrinks with every hit, so later tests
// (in this leaf and in every box after it) only accept nearer ones. True when the query is
// answered: any hit at all, for Query::any.
template <Query kQuery, TriangleVariant kVariant, class Tree, class C>
RT_HD bool intersect_leaf(const Tree& bvh, int first, int count, RayF& ray, TraceHit& hit,
                          C& counters) {
  for (int k = first; k < first + count; ++k) {
    counters.triangle();
    const ch04::TriangleHitF h = ch04::intersect_triangle(kVariant, ray, bvh.triangle(k));
    if (!h.hit) continue;
    hit = {h.t, bvh.triangle_id(k), h.u, h.v};
    ray.tmax = h.t;
    if (kQuery == Query::any) return true;
  }
  return false;
}

// [listing:traverse]
// The closest (or any) hit of `ray` among the tree's triangles: the same answer as testing
// every triangle (chapter 04's closest_hit), up to which of two triangles at exactly the same
// distance is kept.
//
// Each step reads one node and tests the ray against both children's boxes. Leaf children
// are intersected at once; of two interior children the ray enters, the nearer is visited
// next and the other is pushed on the stack. The stack holds at most one node per level
// above the current one, and the build keeps every interior node above depth
// k_max_bvh_depth: the fixed array below cannot overflow.
//
// `Tree` is BvhView here; it may be any type with the same node(), triangle(), triangle_id()
// and node_count (chapter 08 reads the same tree through other memory paths).
template <Query kQuery, TriangleVariant kVariant, class Tree, class C = NoCounters>
RT_HD TraceHit trace_bvh(const Tree& bvh, RayF ray, C&& counters = C{}) {
  TraceHit hit;
  if (bvh.node_count == 0 || !traceable(ray)) return hit;
  const BoxRay box_ray = make_box_ray(ray);
  int stack[k_max_bvh_depth];
  int stack_size = 0;
  int node = 0; // the root
  for (;;) {
    counters.node();
    decltype(auto) n = bvh.node(node); // a reference into memory, or a copy just loaded
    float t0 = 0.0f, t1 = 0.0f;
    bool enter0 = enter_box(n.box[0], box_ray, ray.tmin, ray.tmax, t0);
    bool enter1 = enter_box(n.box[1], box_ray, ray.tmin, ray.tmax, t1);
    if (enter0 && n.is_leaf(0)) {
      if (intersect_leaf<kQuery, kVariant>(bvh, n.first[0], n.count[0], ray, hit, counters))
        return hit;
      enter0 = false;
    }
    if (enter1 && n.is_leaf(1)) {
      if (intersect_leaf<kQuery, kVariant>(bvh, n.first[1], n.count[1], ray, hit, counters))
        return hit;
      enter1 = false;
    }
    if (enter0 && enter1) { // both interior: nearer first, the other later
      // Chosen by selects, not by indexing first[] with a run-time number: a node copied into
      // registers (chapter 08) indexed at run time would have to be stored to local memory.
      const bool second_nearer = t1 < t0;
      stack[stack_size++] = second_nearer ? n.first[0] : n.first[1];
      counters.stack(stack_size);
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
// [/listing:traverse]

// The variant chosen at run time (the CPU paths and tests), compiled in for both.
template <Query kQuery, class Tree, class C = NoCounters>
RT_HD TraceHit trace_bvh(TriangleVariant variant, const Tree& bvh, const RayF& ray,
                         C&& counters = C{}) {
  return variant == TriangleVariant::watertight
             ? trace_bvh<kQuery, TriangleVariant::watertight>(bvh, ray, counters)
             : trace_bvh<kQuery, TriangleVariant::moller_trumbore>(bvh, ray, counters);
}

} // namespace rt::ch07
