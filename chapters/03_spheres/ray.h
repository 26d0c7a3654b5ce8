// Chapter 03: the ray. Templated on the scalar type like every piece of math in the course:
// Ray<float> is what the GPU traces, Ray<double> the float64 reference of the same code.
#pragma once

#include <limits>

#include "rt/vec.h"

namespace rt::ch03 {

template <class T> struct Ray {
  Vec3<T> origin;                              // where the ray starts
  Vec3<T> direction;                           // any length: t is measured in its units
  T tmin = T(0);                               // hits count only for tmin < t < tmax
  T tmax = std::numeric_limits<T>::infinity(); // the closest hit so far, or infinity
};

using RayF = Ray<float>;
using RayD = Ray<double>;

// The same ray in the other precision: the float64 reference of a float ray starts from the
// float-rounded values, so it measures the arithmetic and not the rounding of the inputs.
template <class U, class T> RT_HD Ray<U> ray_as(const Ray<T>& ray) {
  return {ray.origin.template as<U>(), ray.direction.template as<U>(), static_cast<U>(ray.tmin),
          static_cast<U>(ray.tmax)};
}

} // namespace rt::ch03
