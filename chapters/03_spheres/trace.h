// Chapter 03: tracing a pixel through the sphere scene. The primary ray finds the nearest
// sphere; a reflective surface sends a mirror ray on, up to a fixed depth; what no sphere
// catches sees the sky. Shading is only the facing ratio (how squarely the ray meets the
// surface): lights come in chapter 06.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "rt/image.h"
#include "scene.h"
#include "spawn.h"
#include "spheres.h"

namespace rt::ch03 {

template <class T> struct SceneHit {
  T t = std::numeric_limits<T>::infinity();
  int sphere = -1; // -1: the ray hit nothing
};

// Every sphere, keeping the nearest: once a hit is found tmax shrinks to it, so farther
// spheres can only replace it by being nearer still.
template <class T>
RT_HD SceneHit<T> closest_sphere(const SphereScene<T>& scene, Ray<T> ray,
                                 SphereVariant variant) {
  SceneHit<T> closest;
  for (int k = 0; k < scene.count; ++k) {
    const SphereHit<T> hit = intersect_sphere(variant, ray, scene.spheres[k]);
    if (hit.hit) {
      closest = {hit.t, k};
      ray.tmax = hit.t;
    }
  }
  return closest;
}

// Pale near the horizon, blue overhead.
template <class T> RT_HD Vec3<T> sky_colour(Vec3<T> unit_direction) {
  const T s = clamp_to(T(0.5) * (unit_direction.y + T(1)), T(0), T(1));
  return Vec3<T>{T(1), T(1), T(1)} * (T(1) - s) + Vec3<T>{T(0.45), T(0.65), T(1)} * s;
}

// A checkerboard of squares of side `square` on the x-z plane: where hit points land, made
// visible.
template <class T> RT_HD bool dark_square(Vec3<T> p, T square) {
  const long long cell = static_cast<long long>(std::floor(p.x / square)) +
                         static_cast<long long>(std::floor(p.z / square));
  return (cell & 1) != 0;
}

// How a pixel is traced.
struct TraceSettings {
  SphereVariant variant = SphereVariant::stable;
  int max_depth = 4;         // mirror bounces after the primary ray
  float fixed_offset = 0.0f; // > 0: mirror rays start at p + fixed_offset * n instead
};

template <class T> struct PixelTrace {
  Vec3<T> colour; // linear RGB
  T t;            // the primary ray's hit distance (infinity: none)
  int sphere;     // the sphere the primary ray hit, or -1
  int rays;       // rays traced: the primary ray and its mirror rays
};

// [listing:trace_pixel]
template <class T, class Cam>
RT_HD PixelTrace<T> trace_pixel(const SphereScene<T>& scene, const Cam& camera, int i, int j,
                                TraceSettings settings) {
  Ray<T> ray = camera.ray_through_pixel(i, j);
  Vec3<T> colour{}, weight{T(1), T(1), T(1)};
  PixelTrace<T> out{};
  int depth = 0;
  for (;; ++depth) {
    const SceneHit<T> hit = closest_sphere(scene, ray, settings.variant);
    if (depth == 0) out.t = hit.t, out.sphere = hit.sphere;
    const Vec3<T> d = normalize(ray.direction);
    if (hit.sphere < 0) {
      colour += weight * sky_colour(d);
      break;
    }
    const Sphere<T>& sphere = scene.spheres[hit.sphere];
    const Material& material = scene.materials[hit.sphere];
    const Vec3<T> p = ray.origin + ray.direction * hit.t;
    Vec3<T> n = (p - sphere.centre) / sphere.radius;
    if (dot(n, d) > T(0)) n = -n; // the ray is inside: face the normal towards it
    Vec3<T> base = material.colour.as<T>();
    if (material.checkered && dark_square(p, scene.square)) base = base * T(0.3);
    const T mirror = depth < settings.max_depth ? T(material.reflectivity) : T(0);
    const T facing = -dot(n, d);
    colour += weight * base * ((T(1) - mirror) * (T(0.25) + T(0.75) * facing));
    if (mirror == T(0)) break;
    weight = weight * base * mirror; // a tinted mirror
    // The mirror ray starts off the surface by an amount that scales with p (spawn.h), or
    // by the fixed epsilon that the picture of acne asks for.
    const Vec3<T> from = settings.fixed_offset > 0.0f ? p + n * T(settings.fixed_offset)
                                                      : offset_ray_origin(p, n);
    ray = {from, d - n * (T(2) * dot(d, n))};
  }
  out.colour = colour;
  out.rays = depth + 1;
  return out;
}
// [/listing:trace_pixel]

// Linear colour to an 8-bit pixel with gamma 2. A NaN channel becomes 0 (and is counted by
// the caller, never hidden).
template <class T> RT_HD Rgba8 to_rgba8(Vec3<T> c) {
  auto channel = [](T v) -> std::uint8_t {
    if (!(v > T(0))) return 0; // also NaN
    return static_cast<std::uint8_t>(min_of(square_root(v), T(1)) * T(255) + T(0.5));
  };
  return {channel(c.x), channel(c.y), channel(c.z), 255};
}

template <class T> RT_HD bool has_nan(Vec3<T> c) {
  return c.x != c.x || c.y != c.y || c.z != c.z;
}

} // namespace rt::ch03
