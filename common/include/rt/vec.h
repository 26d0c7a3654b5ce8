// Small fixed-size vectors templated on the scalar type: Vec3<float> is what the GPU traces
// with, Vec3<double> is the float64 reference of the same code. Introduced in chapter 01.
#pragma once

#include "rt/hd.h"
#include "rt/scalar.h"

namespace rt {

template <class T> struct Vec2 {
  T x{}, y{};

  RT_HD constexpr T operator[](int i) const { return i == 0 ? x : y; }
};

template <class T> struct Vec3 {
  T x{}, y{}, z{};

  RT_HD constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  template <class U> RT_HD constexpr Vec3<U> as() const {
    return {static_cast<U>(x), static_cast<U>(y), static_cast<U>(z)};
  }
};

using Vec2f = Vec2<float>;
using Vec2d = Vec2<double>;
using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;

// clang-format off
template <class T> RT_HD constexpr Vec2<T> operator+(Vec2<T> a, Vec2<T> b) { return {a.x + b.x, a.y + b.y}; }
template <class T> RT_HD constexpr Vec2<T> operator-(Vec2<T> a, Vec2<T> b) { return {a.x - b.x, a.y - b.y}; }
template <class T> RT_HD constexpr Vec2<T> operator*(Vec2<T> a, T s) { return {a.x * s, a.y * s}; }
template <class T> RT_HD constexpr Vec2<T> operator*(T s, Vec2<T> a) { return a * s; }
template <class T> RT_HD constexpr bool operator==(Vec2<T> a, Vec2<T> b) { return a.x == b.x && a.y == b.y; }

template <class T> RT_HD constexpr Vec3<T> operator+(Vec3<T> a, Vec3<T> b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T> RT_HD constexpr Vec3<T> operator-(Vec3<T> a, Vec3<T> b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T> RT_HD constexpr Vec3<T> operator-(Vec3<T> a) { return {-a.x, -a.y, -a.z}; }
template <class T> RT_HD constexpr Vec3<T> operator*(Vec3<T> a, Vec3<T> b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
template <class T> RT_HD constexpr Vec3<T> operator*(Vec3<T> a, T s) { return {a.x * s, a.y * s, a.z * s}; }
template <class T> RT_HD constexpr Vec3<T> operator*(T s, Vec3<T> a) { return a * s; }
template <class T> RT_HD constexpr Vec3<T> operator/(Vec3<T> a, T s) { return {a.x / s, a.y / s, a.z / s}; }
template <class T> RT_HD constexpr Vec3<T>& operator+=(Vec3<T>& a, Vec3<T> b) { return a = a + b; }
template <class T> RT_HD constexpr Vec3<T>& operator-=(Vec3<T>& a, Vec3<T> b) { return a = a - b; }
template <class T> RT_HD constexpr Vec3<T>& operator*=(Vec3<T>& a, T s) { return a = a * s; }
template <class T> RT_HD constexpr bool operator==(Vec3<T> a, Vec3<T> b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
template <class T> RT_HD constexpr bool operator!=(Vec3<T> a, Vec3<T> b) { return !(a == b); }

template <class T> RT_HD constexpr T dot(Vec3<T> a, Vec3<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> RT_HD constexpr T length_squared(Vec3<T> a) { return dot(a, a); }
template <class T> RT_HD inline T length(Vec3<T> a) { return square_root(length_squared(a)); }
template <class T> RT_HD inline Vec3<T> normalize(Vec3<T> a) { return a / length(a); }
template <class T> RT_HD constexpr Vec3<T> elementwise_min(Vec3<T> a, Vec3<T> b) { return {min_of(a.x, b.x), min_of(a.y, b.y), min_of(a.z, b.z)}; }
template <class T> RT_HD constexpr Vec3<T> elementwise_max(Vec3<T> a, Vec3<T> b) { return {max_of(a.x, b.x), max_of(a.y, b.y), max_of(a.z, b.z)}; }
template <class T> RT_HD constexpr T min_component(Vec3<T> a) { return min_of(a.x, min_of(a.y, a.z)); }
template <class T> RT_HD constexpr T max_component(Vec3<T> a) { return max_of(a.x, max_of(a.y, a.z)); }
template <class T> RT_HD inline Vec3<T> elementwise_abs(Vec3<T> a) { return {absolute(a.x), absolute(a.y), absolute(a.z)}; }
// clang-format on

// The cross product through difference_of_products: each component is a 2x2 determinant,
// and the naive form loses every significant digit when the vectors are nearly parallel.
template <class T> RT_HD inline Vec3<T> cross(Vec3<T> a, Vec3<T> b) {
  return {difference_of_products(a.y, b.z, a.z, b.y),
          difference_of_products(a.z, b.x, a.x, b.z),
          difference_of_products(a.x, b.y, a.y, b.x)};
}

} // namespace rt
