// Chapter 04: the ray/triangle intersection, twice. Möller–Trumbore is short and fast but
// lets rays slip between two triangles that share an edge; the watertight test does not.
#pragma once

#include <limits>

#include "ray.h"
#include "rt/scalar.h"
#include "rt/vec.h"

namespace rt::ch04 {

using ch03::Ray;

template <class T> struct Triangle { Vec3<T> v0, v1, v2; };

template <class T> struct TriangleHit {
  bool hit = false;     // false: the other fields mean nothing
  T t = T(0);           // the hit point is origin + t * direction
  T u = T(0), v = T(0); // barycentrics: the hit point is (1-u-v) v0 + u v1 + v v2
};

using TriangleF = Triangle<float>;
using TriangleD = Triangle<double>;
using TriangleHitF = TriangleHit<float>;
using TriangleHitD = TriangleHit<double>;

// False for infinities and NaN (every comparison with NaN is false).
template <class T> RT_HD inline bool is_finite(T x) {
  return absolute(x) <= std::numeric_limits<T>::max();
}

// Möller & Trumbore 1997, two-sided: solve o + t d = v0 + u e1 + v e2 by Cramer's rule. Each
// triangle measures u and v from its own v0 and edges, so two triangles sharing an edge round
// their edge tests differently, and a ray through the edge can fail both.
// [listing:moller_trumbore]
template <class T> RT_HD TriangleHit<T> intersect_moller_trumbore(Ray<T> ray, Triangle<T> tri) {
  const Vec3<T> edge1 = tri.v1 - tri.v0;
  const Vec3<T> edge2 = tri.v2 - tri.v0;
  const Vec3<T> p = cross(ray.direction, edge2);
  // The paper's det = e1 . (d x e2), grouped as d . (e2 x e1): the same triple product, but
  // for collinear edges cross() (exact in sign) gives exactly 0 and the triangle is rejected,
  // where e1 . p would leave rounding noise that passes the tests below at random.
  const T det = dot(ray.direction, cross(edge2, edge1));
  // Only a zero or non-finite determinant is rejected. det scales with |d| |e1| |e2|: the
  // usual |det| < 1e-6 cull rejects every triangle with legs below 1e-3 at unit distance.
  if (det == T(0) || !is_finite(det)) return {};
  const T inv_det = T(1) / det;
  const Vec3<T> s = ray.origin - tri.v0;
  const T u = dot(s, p) * inv_det;
  if (!(u >= T(0) && u <= T(1))) return {}; // written so that NaN rejects
  const Vec3<T> q = cross(s, edge1);
  const T v = dot(ray.direction, q) * inv_det;
  if (!(v >= T(0) && u + v <= T(1))) return {};
  const T t = dot(edge2, q) * inv_det;
  if (!(t > ray.tmin && t < ray.tmax)) return {};
  return {true, t, u, v};
}
// [/listing:moller_trumbore]

template <class T> struct WatertightRay;

// Which coordinate goes where: the frame's own axes, read at run time...
struct AxesOfFrame {
  template <class T> RT_HD static int x(const WatertightRay<T>& f) { return f.kx; }
  template <class T> RT_HD static int y(const WatertightRay<T>& f) { return f.ky; }
  template <class T> RT_HD static int z(const WatertightRay<T>& f) { return f.kz; }
};
// ...or fixed when the code is compiled, by a caller that has told its rays' six cases apart
// (chapter 09's CPU traversal): each a[k] below is then a register, not a chain of branches.
// The arithmetic is the same either way.
template <int X, int Y, int Z> struct FixedAxes {
  template <class T> RT_HD static constexpr int x(const WatertightRay<T>&) { return X; }
  template <class T> RT_HD static constexpr int y(const WatertightRay<T>&) { return Y; }
  template <class T> RT_HD static constexpr int z(const WatertightRay<T>&) { return Z; }
};

// Woop, Benthin & Wald 2013, "Watertight Ray/Triangle Intersection", two-sided. The vertices
// move into a frame where the ray is the +z axis from the origin; then the hit test is three
// 2D edge functions of the moved vertices. A vertex shared by several triangles moves to the
// same point in all of them (same ray, same arithmetic), so the moved triangles still form a
// closed mesh; with edge functions of exact sign the test is then the exact point-in-triangle
// test on that mesh, which covers the origin at a shared edge and at a shared vertex alike.
// [listing:watertight_frame]
// Steps 1 and 2 depend on the ray alone: a traversal that tests many triangles against one ray
// can make this once (chapter 09's CPU traversal does).
template <class T> struct WatertightRay {
  Ray<T> ray;
  int kx, ky, kz;              // the permuted axes
  T shear_x, shear_y, shear_z; // the shear that makes the direction (0, 0, 1)
};

template <class T> RT_INLINE_ON_CPU RT_HD inline WatertightRay<T> watertight_ray(Ray<T> ray) {
  // 1. Permute the axes so that z is the direction's largest component (no division by a
  // small number), swapping x and y when z is negative to keep the winding.
  const Vec3<T> d = ray.direction;
  const Vec3<T> d_abs = elementwise_abs(d);
  const int kz =
      d_abs.x >= d_abs.y ? (d_abs.x >= d_abs.z ? 0 : 2) : (d_abs.y >= d_abs.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  if (d[kz] < T(0)) {
    const int swap = kx;
    kx = ky;
    ky = swap;
  }
  // 2. Shear so the direction becomes (0, 0, 1). NaN or zero directions make NaN here, and
  // NaN fails the inside test below.
  return {ray, kx, ky, kz, d[kx] / d[kz], d[ky] / d[kz], T(1) / d[kz]};
}

template <class T, class Axes = AxesOfFrame>
RT_INLINE_ON_CPU RT_HD inline TriangleHit<T> intersect_watertight(const WatertightRay<T>& frame,
                                                                  Triangle<T> tri, Axes = {}) {
  const Ray<T>& ray = frame.ray;
  const int kx = Axes::x(frame), ky = Axes::y(frame), kz = Axes::z(frame);
  const T shear_x = frame.shear_x, shear_y = frame.shear_y, shear_z = frame.shear_z;
  const Vec3<T> a = tri.v0 - ray.origin, b = tri.v1 - ray.origin, c = tri.v2 - ray.origin;
  // Explicit FMAs: whatever the compiler's contraction setting, a vertex moves to the same
  // point in every triangle that shares it.
  const T ax = fused_multiply_add(-shear_x, a[kz], a[kx]);
  const T ay = fused_multiply_add(-shear_y, a[kz], a[ky]);
  const T bx = fused_multiply_add(-shear_x, b[kz], b[kx]);
  const T by = fused_multiply_add(-shear_y, b[kz], b[ky]);
  const T cx = fused_multiply_add(-shear_x, c[kz], c[kx]);
  const T cy = fused_multiply_add(-shear_y, c[kz], c[ky]);
  // [/listing:watertight_frame]
  // 3. Edge functions: twice the signed areas of the triangles the origin makes with each
  // edge. Two triangles sharing an edge evaluate the same 2x2 determinant with its rows
  // swapped. A plainly rounded a*b - c*d gives them exactly opposite values, but nvcc contracts
  // it to fma(a, b, -c*d), which rounds the two differently, and then both can come out on the
  // outside. difference_of_products has a relative error below 2u (Jeannerod, Louvet & Muller
  // 2013): its two values differ in the last bits, but each has the exact sign, whatever the
  // contraction setting, and is 0 only when the exact value is. The paper instead recomputes
  // an edge function in double when float gives exactly 0. Exact signs hold while the products
  // stay clear of float underflow (coordinates above ~1e-15).
  // [listing:watertight_edges]
  const T u_edge = difference_of_products(cx, by, cy, bx); // edge v1 v2: weight of v0
  const T v_edge = difference_of_products(ax, cy, ay, cx); // edge v2 v0: weight of v1
  const T w_edge = difference_of_products(bx, ay, by, ax); // edge v0 v1: weight of v2
  const bool inside = (u_edge >= T(0) && v_edge >= T(0) && w_edge >= T(0)) ||
                      (u_edge <= T(0) && v_edge <= T(0) && w_edge <= T(0));
  if (!inside) return {};
  const T det = u_edge + v_edge + w_edge;
  if (det == T(0)) return {}; // the ray lies in the plane, or the triangle is a segment
  // [/listing:watertight_edges]
  // [listing:watertight_distance]
  // 4. Distance: interpolate the moved z coordinates, scaled back to units of d. The sum is
  // fused explicitly, as above: nvcc would contract it on the GPU and not on the CPU, and the
  // two backends would round t differently.
  const T t_times_det = fused_multiply_add(
      u_edge, shear_z * a[kz],
      fused_multiply_add(v_edge, shear_z * b[kz], w_edge * (shear_z * c[kz])));
  const T inv_det = T(1) / det;
  const T t = t_times_det * inv_det;
  if (!(t > ray.tmin && t < ray.tmax)) return {};
  return {true, t, v_edge * inv_det, w_edge * inv_det};
}
// [/listing:watertight_distance]

// Calls fn(FixedAxes<...>{}) with the frame's own permutation, one of six: the largest
// direction component (kz) and the order of the other two. For a caller that compiles its
// triangle test once per case (chapter 09's CPU traversal).
template <class T, class Fn>
decltype(auto) with_fixed_axes(const WatertightRay<T>& frame, Fn fn) {
  switch (frame.kz * 3 + frame.kx) {
  case 0 * 3 + 1:
    return fn(FixedAxes<1, 2, 0>{});
  case 0 * 3 + 2:
    return fn(FixedAxes<2, 1, 0>{});
  case 1 * 3 + 2:
    return fn(FixedAxes<2, 0, 1>{});
  case 1 * 3 + 0:
    return fn(FixedAxes<0, 2, 1>{});
  case 2 * 3 + 0:
    return fn(FixedAxes<0, 1, 2>{});
  default:
    return fn(FixedAxes<1, 0, 2>{}); // kz 2, kx 1: watertight_ray makes no other case
  }
}

// The test in one call, as every chapter but 09's CPU traversal uses it.
template <class T> RT_HD TriangleHit<T> intersect_watertight(Ray<T> ray, Triangle<T> tri) {
  return intersect_watertight(watertight_ray(ray), tri);
}

} // namespace rt::ch04
