// Chapter 03: cameras turn a pixel into a ray. The pinhole camera is exactly the one of the
// benchmark protocol, so hit buffers compare with other ray tracers pixel for pixel.
#pragma once

#include <cmath>
#include <numbers>

#include "error_free.h"
#include "ray.h"
#include "rt/vec.h"

namespace rt::ch03 {

// Vector steps of the benchmark formula with every product rounded on its own: nvcc would
// otherwise fuse products into adds, and a GPU ray would differ from the CPU's (and from other
// ray tracers') in the last bits, enough to flip tiny normal components on axis-aligned walls.
template <class T> RT_HD inline T dot_as_written(Vec3<T> a, Vec3<T> b) {
  return rounded_product(a.x, b.x) + rounded_product(a.y, b.y) + rounded_product(a.z, b.z);
}
template <class T> RT_HD inline Vec3<T> normalize_as_written(Vec3<T> a) {
  return a / square_root(dot_as_written(a, a));
}
template <class T> RT_HD inline Vec3<T> cross_as_written(Vec3<T> a, Vec3<T> b) {
  return {rounded_product(a.y, b.z) - rounded_product(a.z, b.y),
          rounded_product(a.z, b.x) - rounded_product(a.x, b.z),
          rounded_product(a.x, b.y) - rounded_product(a.y, b.x)};
}
// s*a + t*b + c, left to right, each product rounded.
template <class T>
RT_HD inline Vec3<T> combine_as_written(T s, Vec3<T> a, T t, Vec3<T> b, Vec3<T> c) {
  return {rounded_product(s, a.x) + rounded_product(t, b.x) + c.x,
          rounded_product(s, a.y) + rounded_product(t, b.y) + c.y,
          rounded_product(s, a.z) + rounded_product(t, b.z) + c.z};
}

// Screen coordinates of a pixel centre in [-1, 1]: x grows to the right, y grows upwards
// (row 0 is the top row).
template <class T> RT_HD inline T screen_x(int i, int width) {
  return T(2) * (T(i) + T(0.5)) / T(width) - T(1);
}
template <class T> RT_HD inline T screen_y(int j, int height) {
  return T(1) - T(2) * (T(j) + T(0.5)) / T(height);
}

// An orthonormal view basis looking from eye to target: up is the world up made
// perpendicular to forward.
template <class T> struct ViewBasis {
  Vec3<T> forward; // unit, from the eye towards the target
  Vec3<T> right;   // unit, normalize(cross(forward, world_up))
  Vec3<T> up;      // cross(right, forward)
};

template <class T> ViewBasis<T> look_at(Vec3<T> eye, Vec3<T> target, Vec3<T> world_up) {
  const Vec3<T> forward = normalize_as_written(target - eye);
  const Vec3<T> right = normalize_as_written(cross_as_written(forward, world_up));
  return {forward, right, cross_as_written(right, forward)};
}

template <class T> struct PinholeCamera {
  Vec3<T> eye;        // every ray starts here
  ViewBasis<T> basis; // where the camera looks
  T tan_half_vfov;    // tan(vertical field of view / 2)
  T aspect;           // width / height
  int width, height;  // image size in pixels

  // [listing:pinhole_ray]
  // Pixel (i, j): column i from the left, row j from the top.
  RT_HD Ray<T> ray_through_pixel(int i, int j) const {
    const T sx = rounded_product(rounded_product(screen_x<T>(i, width), tan_half_vfov), aspect);
    const T sy = rounded_product(screen_y<T>(j, height), tan_half_vfov);
    const Vec3<T> direction =
        normalize_as_written(combine_as_written(sx, basis.right, sy, basis.up, basis.forward));
    return {eye, direction};
  }
  // [/listing:pinhole_ray]
};

// The benchmark camera: eye, target, world up, vertical field of view in degrees, image size.
template <class T>
PinholeCamera<T> make_pinhole_camera(Vec3<T> eye, Vec3<T> target, Vec3<T> world_up,
                                     T vfov_degrees, int width, int height) {
  const T half_vfov = vfov_degrees * std::numbers::pi_v<T> / T(180) / T(2);
  return {.eye = eye,
          .basis = look_at(eye, target, world_up),
          .tan_half_vfov = std::tan(half_vfov),
          .aspect = T(width) / T(height),
          .width = width,
          .height = height};
}

// Parallel rays from a rectangle of the view plane: every ray has the direction forward.
template <class T> struct OrthographicCamera {
  Vec3<T> eye;        // centre of the view rectangle
  ViewBasis<T> basis; // where the camera looks
  T half_height;      // half the view rectangle's height, in world units
  T aspect;           // width / height
  int width, height;  // image size in pixels

  // [listing:orthographic_ray]
  RT_HD Ray<T> ray_through_pixel(int i, int j) const {
    const T sx = rounded_product(rounded_product(screen_x<T>(i, width), half_height), aspect);
    const T sy = rounded_product(screen_y<T>(j, height), half_height);
    return {combine_as_written(sx, basis.right, sy, basis.up, eye), basis.forward};
  }
  // [/listing:orthographic_ray]
};

template <class T>
OrthographicCamera<T> make_orthographic_camera(Vec3<T> eye, Vec3<T> target, Vec3<T> world_up,
                                               T view_height, int width, int height) {
  return {.eye = eye,
          .basis = look_at(eye, target, world_up),
          .half_height = view_height / T(2),
          .aspect = T(width) / T(height),
          .width = width,
          .height = height};
}

} // namespace rt::ch03
