// Scalar helpers that pick the right float/double math function on host and device alike,
// so templated math (Vec3<float>, Vec3<double>) compiles for both backends.
#pragma once

#include <cmath>

#include "rt/hd.h"

namespace rt {

RT_HD inline float fused_multiply_add(float a, float b, float c) { return fmaf(a, b, c); }
RT_HD inline double fused_multiply_add(double a, double b, double c) { return fma(a, b, c); }
RT_HD inline float square_root(float x) { return sqrtf(x); }
RT_HD inline double square_root(double x) { return sqrt(x); }
RT_HD inline float absolute(float x) { return fabsf(x); }
RT_HD inline double absolute(double x) { return fabs(x); }

template <class T> RT_HD constexpr T min_of(T a, T b) { return b < a ? b : a; }
template <class T> RT_HD constexpr T max_of(T a, T b) { return a < b ? b : a; }
template <class T> RT_HD constexpr T clamp_to(T x, T lo, T hi) {
  return min_of(max_of(x, lo), hi);
}

// a*b - c*d without catastrophic cancellation (Kahan's algorithm): the rounding error of c*d
// is recovered exactly by an FMA and added back, so the result is within 1.5 ulp even when
// a*b and c*d almost cancel. Every operation is explicit, so compiler FMA contraction
// (nvcc's default) cannot change the result.
// [listing:difference_of_products]
template <class T> RT_HD inline T difference_of_products(T a, T b, T c, T d) {
  const T cd = c * d;
  const T cd_error = fused_multiply_add(-c, d, cd);
  const T ab_minus_cd = fused_multiply_add(a, b, -cd);
  return ab_minus_cd + cd_error;
}
// [/listing:difference_of_products]

} // namespace rt
