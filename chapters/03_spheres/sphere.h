// Chapter 03: the ray/sphere intersection, twice. The textbook quadratic loses every digit of
// its discriminant for small spheres far away; the stable form keeps them.
#pragma once

#include "error_free.h"
#include "ray.h"
#include "rt/vec.h"

namespace rt::ch03 {

template <class T> struct Sphere {
  Vec3<T> centre;
  T radius;
};

template <class T> struct SphereHit {
  bool hit = false; // false: t means nothing
  T t = T(0);       // the hit point is origin + t * direction
};

using SphereF = Sphere<float>;
using SphereD = Sphere<double>;
using SphereHitF = SphereHit<float>;
using SphereHitD = SphereHit<double>;

// The nearest of two roots inside (tmin, tmax): the near one, else the far one (the ray starts
// inside the sphere). Comparisons are written so that a NaN root is never accepted.
template <class T> RT_HD inline SphereHit<T> nearest_root_in_range(T near, T far, Ray<T> ray) {
  if (near > ray.tmin && near < ray.tmax) return {true, near};
  if (far > ray.tmin && far < ray.tmax) return {true, far};
  return {};
}

// |o - c|^2 - r^2 with a rounding error of about one ulp of the result: each square and the
// sum are kept as value + exact error (Ogita, Rump & Oishi's Dot2). Computed plainly, the
// products round at the scale of |o - c|^2, and when the ray starts close to a large sphere
// (an eye above a ground sphere, a shadow ray leaving a surface) the result is all noise.
// [listing:power_of_point]
template <class T> RT_HD inline T power_of_point(Vec3<T> centre_to_origin, T radius) {
  const ValueAndError<T> xx = two_product(centre_to_origin.x, centre_to_origin.x);
  const ValueAndError<T> yy = two_product(centre_to_origin.y, centre_to_origin.y);
  const ValueAndError<T> zz = two_product(centre_to_origin.z, centre_to_origin.z);
  const ValueAndError<T> rr = two_product(radius, radius);
  ValueAndError<T> sum = two_sum(xx.value, yy.value);
  T error = sum.error + xx.error + yy.error;
  sum = two_sum(sum.value, zz.value);
  error += sum.error + zz.error;
  sum = two_sum(sum.value, -rr.value);
  error += sum.error - rr.error;
  return sum.value + error;
}
// [/listing:power_of_point]

// The textbook form: a t^2 + b t + c = 0 and b^2 - 4ac. For a sphere at distance D, b^2 and
// 4ac are both about 4 D^2 and their difference, about 4 r^2, is what remains after
// cancellation: at D = 1e4 r in float it is rounding noise, and rays hit or miss at random.
// [listing:sphere_textbook]
template <class T> RT_HD SphereHit<T> intersect_sphere_textbook(Ray<T> ray, Sphere<T> sphere) {
  const Vec3<T> oc = ray.origin - sphere.centre;
  const T a = dot(ray.direction, ray.direction);
  const T b = T(2) * dot(oc, ray.direction);
  const T c = dot(oc, oc) - sphere.radius * sphere.radius;
  const T discriminant = b * b - T(4) * a * c;
  if (!(discriminant >= T(0))) return {}; // a miss, or NaN
  const T root = square_root(discriminant);
  return nearest_root_in_range((-b - root) / (T(2) * a), (-b + root) / (T(2) * a), ray);
}
// [/listing:sphere_textbook]

// The stable form (after Haines et al., Ray Tracing Gems ch. 7). With f = o - c the roots of
// a t^2 - 2 beta t + c = 0 (beta = -f.d, c = |f|^2 - r^2) are (beta +- sqrt(a disc)) / a,
// where disc = r^2 - |l|^2 and l = f + (beta/a) d runs from the centre to the point of the
// ray's line closest to it. Both roots come from q = beta + sign(beta) sqrt(a disc), an
// addition of like signs: t = q / a and t = c / q, so neither root cancels.
// [listing:sphere_stable]
template <class T> RT_HD SphereHit<T> intersect_sphere_stable(Ray<T> ray, Sphere<T> sphere) {
  const Vec3<T> f = ray.origin - sphere.centre;
  const Vec3<T> d = ray.direction;
  const T a = dot(d, d);
  const T beta = -dot(f, d);
  const T c = power_of_point(f, sphere.radius);
  const Vec3<T> l = f + d * (beta / a);
  const T l_squared = dot(l, l);
  const T beta_squared_over_a = beta * beta / a;
  // r^2 - |l|^2 and beta^2/a - c are the same number, rounded differently. Far from a small
  // sphere beta^2/a ~ |f|^2 is huge and only the geometric form is accurate: l is short, with
  // errors of a few ulps of |f|. Close to a huge sphere l is as long as f, the geometric form
  // errs by ulps of r^2, and beta^2/a is the smaller term: with c compensated, the algebraic
  // form is accurate. So the form with the smaller subtracted term is taken.
  const T discriminant = beta_squared_over_a < l_squared
                             ? beta_squared_over_a - c
                             : sphere.radius * sphere.radius - l_squared;
  if (!(discriminant >= T(0))) return {}; // a miss, or NaN
  const T root = square_root(a * discriminant);
  const T q = beta < T(0) ? beta - root : beta + root;
  const T t_from_q = q / a, t_from_c = c / q;
  return nearest_root_in_range(min_of(t_from_q, t_from_c), max_of(t_from_q, t_from_c), ray);
}
// [/listing:sphere_stable]

} // namespace rt::ch03
