// Chapter 03: where a secondary ray (shadow, reflection) starts. A hit point computed in float
// lies a few ulps off the surface, on either side, and a ray started there can hit its own
// surface again at t ~ 0: the speckled "shadow acne".
#pragma once

#include <limits>

#include "rt/vec.h"

namespace rt::ch03 {

// Moves a hit point p off its surface along the unit normal n (on the side the new ray
// leaves to). The distance scales with the largest coordinate of p because rounding errors
// do: an ulp of 1e6 is 0.06 in float. A fixed epsilon cannot serve every scale: 1e-4 is nearly
// a thousand ulps at 1 and less than one ulp at 1e6, where p + 1e-4 n rounds back to p.
// k_relative (128 ulps) covers the hit point's own error and that of the intersection test
// repeated from the offset origin, with a wide margin. Points nearer the origin than 2^-32,
// where ulps vanish, are moved as far as a point at 2^-32. The scaling assumes p is accurate
// to a few ulps of its own largest coordinate, which holds while the ray's origin and the
// surface are not far larger in magnitude than p. (A hit near the world origin on a sphere
// centred 1e6 away is not: its error is ulps of 1e6.) Where it does not, `scale` names the
// largest coordinate the point was computed from, and the offset follows that instead.
// [listing:offset_ray_origin]
template <class T> RT_HD inline Vec3<T> offset_ray_origin(Vec3<T> p, Vec3<T> n, T scale) {
  constexpr T k_relative = T(128) * std::numeric_limits<T>::epsilon();
  constexpr T k_magnitude_floor = T(1) / T(65536) / T(65536);
  const T magnitude = max_of(scale, k_magnitude_floor);
  return p + n * (k_relative * magnitude);
}
template <class T> RT_HD inline Vec3<T> offset_ray_origin(Vec3<T> p, Vec3<T> n) {
  return offset_ray_origin(p, n, max_component(elementwise_abs(p)));
}
// [/listing:offset_ray_origin]

} // namespace rt::ch03
