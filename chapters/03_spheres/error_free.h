// Chapter 03: arithmetic whose rounding the compiler cannot change. nvcc contracts a*b + c
// into one FMA by default; that is usually harmless, but it breaks the error-free
// transformations below and changes camera rays bit for bit between the GPU and the CPU.
#pragma once

#include "rt/hd.h"
#include "rt/scalar.h"

namespace rt::ch03 {

// x*y rounded on its own: on the device __fmul_rn is never fused into a following add. Host
// compilers on x86-64 emit no FMA unless -march asks for one, so plain x*y is already rounded.
// [listing:rounded_product]
RT_HD inline float rounded_product(float x, float y) {
#if RT_ON_DEVICE
  return __fmul_rn(x, y);
#else
  return x * y;
#endif
}
// [/listing:rounded_product]
RT_HD inline double rounded_product(double x, double y) {
#if RT_ON_DEVICE
  return __dmul_rn(x, y);
#else
  return x * y;
#endif
}

// A rounded result and its rounding error: value + error is the exact result.
template <class T> struct ValueAndError {
  T value;
  T error;
};

// [listing:error_free]
// Knuth's TwoSum: fl(a + b) and its exact rounding error, with additions only.
template <class T> RT_HD inline ValueAndError<T> two_sum(T a, T b) {
  const T sum = a + b;
  const T b_part = sum - a;
  const T a_part = sum - b_part;
  return {sum, (a - a_part) + (b - b_part)};
}

// fl(a * b) and its exact rounding error, which one FMA recovers.
template <class T> RT_HD inline ValueAndError<T> two_product(T a, T b) {
  const T product = rounded_product(a, b);
  return {product, fused_multiply_add(a, b, -product)};
}
// [/listing:error_free]

} // namespace rt::ch03
