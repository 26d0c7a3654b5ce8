// Chapter 06: Lambertian shading of a triangle mesh, one ray at a time, on either backend and
// in either precision. The nearest triangle (chapter 04's watertight test) gives t, u and v;
// the normal is the face's or one interpolated from the vertices'; each light adds its share
// by Lambert's cosine law unless a shadow ray finds something in the way.
#pragma once

#include <cstdint>
#include <limits>

#include "feature_sets.h"
#include "lights.h"
#include "spawn.h"
#include "trace.h"
#include "triangles.h"

namespace rt::ch06 {

using ch03::Ray;
using ch04::IndexedTriangle;
using ch04::MeshView;

// The scene as per-ray code reads it: host pointers on the CPU, device pointers on the GPU.
// Arrays a kernel's features do not read may be null.
template <class Geometry> struct SceneViewOf {
  Geometry mesh;                         // positions and triangles (and what traces them)
  const std::uint8_t* material;          // per triangle: its slot in the palette
  const Vec3f* normals;                  // vertex normals: smooth shading only
  const IndexedTriangle* normal_indices; // per triangle, into normals: smooth shading only
  Palette palette;                       // albedo per slot
  Lights lights;                         // by value
  bool lift_shadow_origins = true;       // Hanika's lift; off only to show what it removes
};
// This chapter traces every ray against every triangle of a MeshView (brute force). A later
// chapter passes its own geometry type with its own closest_surface, occluded and triangle_as:
// the shading below calls them unqualified, so the geometry's namespace provides them.
using SceneView = SceneViewOf<MeshView>;

template <class T> struct SurfaceHit {
  T t = std::numeric_limits<T>::infinity();
  int triangle = -1;    // -1: the ray hit nothing
  T u = T(0), v = T(0); // barycentrics: the point is (1-u-v) v0 + u v1 + v v2
};

// Triangle i in precision T: the float64 reference converts each float vertex exactly.
template <class T> RT_HD ch04::Triangle<T> triangle_as(const MeshView& mesh, int i) {
  const IndexedTriangle k = mesh.triangles[i];
  return {mesh.vertices[k.v0].template as<T>(), mesh.vertices[k.v1].template as<T>(),
          mesh.vertices[k.v2].template as<T>()};
}

// Every triangle, keeping the nearest (brute force, as in chapter 04).
template <class T> RT_HD SurfaceHit<T> closest_surface(const MeshView& mesh, Ray<T> ray) {
  SurfaceHit<T> nearest;
  for (int i = 0; i < mesh.triangle_count; ++i) {
    const ch04::TriangleHit<T> hit = ch04::intersect_watertight(ray, triangle_as<T>(mesh, i));
    if (hit.hit) {
      nearest = {hit.t, i, hit.u, hit.v};
      ray.tmax = hit.t;
    }
  }
  return nearest;
}

// A shadow ray needs any hit, not the nearest: it stops at the first.
template <class T> RT_HD bool occluded(const MeshView& mesh, const Ray<T>& ray) {
  for (int i = 0; i < mesh.triangle_count; ++i)
    if (ch04::intersect_watertight(ray, triangle_as<T>(mesh, i)).hit) return true;
  return false;
}

// v at unit length, or `fallback` where v has no direction: zero (a sliver triangle, vertex
// normals that cancel) or not finite. Dividing by the largest component first keeps the
// squared length clear of underflow and overflow.
// [listing:unit_or]
template <class T> RT_HD Vec3<T> unit_or(Vec3<T> v, Vec3<T> fallback) {
  const T largest = max_component(elementwise_abs(v));
  const bool finite = ch04::is_finite(v.x) && ch04::is_finite(v.y) && ch04::is_finite(v.z);
  if (!(finite && largest > T(0))) return fallback;
  const Vec3<T> scaled = v / largest;
  return scaled / length(scaled);
}
// [/listing:unit_or]

// The vertex normals blended with the hit's barycentrics, not yet unit length.
template <class T, class S>
RT_HD Vec3<T> interpolated_normal(const S& scene, const SurfaceHit<T>& hit) {
  const IndexedTriangle k = scene.normal_indices[hit.triangle];
  const T w = T(1) - hit.u - hit.v;
  return scene.normals[k.v0].template as<T>() * w +
         scene.normals[k.v1].template as<T>() * hit.u +
         scene.normals[k.v2].template as<T>() * hit.v;
}

template <class T> struct ShadedSample {
  Vec3<T> colour{};        // linear RGB
  int triangle = -1;       // the primary hit, -1 for none
  int shadow_rays = 0;     // shadow rays traced
  int shadowed_facing = 0; // of them, blocked although the face itself faces the light
};

template <class T> struct ShadingPoint {
  Vec3<T> position;    // the hit point
  Vec3<T> shadow_from; // where shadow rays leave from, before chapter 03's offset
  Vec3<T> geometric;   // unit, the face's normal turned towards the viewer
  Vec3<T> shading;     // unit, what Lambert's law uses: the geometric or the interpolated one
};

// n, turned to the side of the surface that `side` points to.
template <class T> RT_HD Vec3<T> faced(Vec3<T> n, Vec3<T> side) {
  return dot(n, side) < T(0) ? -n : n;
}

// Hanika 2021, "Hacking the shadow terminator": the smooth surface that vertex normals describe
// bulges above the flat triangle, and shadow rays from the triangle itself are blocked by the
// triangle's own neighbours where the smooth normal still faces the light: a jagged shadow
// along the facets. Lifting p by its depth below the plane across each vertex normal, blended
// like the normals, starts shadow rays near the smooth surface instead.
// [listing:shadow_terminator]
template <class T, class S>
RT_HD Vec3<T> lifted_point(const S& scene, const ch04::Triangle<T>& tri,
                           const SurfaceHit<T>& hit, Vec3<T> p, Vec3<T> geometric) {
  const IndexedTriangle k = scene.normal_indices[hit.triangle];
  const Vec3<T> vertex[3] = {tri.v0, tri.v1, tri.v2};
  const int normal[3] = {k.v0, k.v1, k.v2};
  const T weight[3] = {T(1) - hit.u - hit.v, hit.u, hit.v};
  Vec3<T> lifted = p;
  for (int i = 0; i < 3; ++i) {
    const Vec3<T> n =
        faced(unit_or(scene.normals[normal[i]].template as<T>(), geometric), geometric);
    const T depth = max_of(dot(vertex[i] - p, n), T(0)); // 0 where p is above the plane
    lifted += n * (weight[i] * depth);
  }
  return lifted;
}
// [/listing:shadow_terminator]

// [listing:shading_point]
template <class T, class F, class S>
RT_HD ShadingPoint<T> shading_point(const S& scene, const Ray<T>& ray, const SurfaceHit<T>& hit,
                                    F features) {
  const ch04::Triangle<T> tri = triangle_as<T>(scene.mesh, hit.triangle);
  const Vec3<T> d = normalize(ray.direction);
  // A sliver the watertight test accepts may have no float normal: face the viewer then.
  const Vec3<T> geometric =
      faced(unit_or(cross(tri.v1 - tri.v0, tri.v2 - tri.v0), -d), -d); // two-sided
  const Vec3<T> p = ray.origin + ray.direction * hit.t;
  ShadingPoint<T> point{p, p, geometric, geometric}; // flat
  if constexpr (F::compiled(k_smooth_normals)) {
    if (features.on(k_smooth_normals)) {
      // A blend of zero length (opposite vertex normals) falls back to the face's normal.
      point.shading = faced(unit_or(interpolated_normal(scene, hit), geometric), geometric);
      if constexpr (F::compiled(k_shadows))
        if (features.on(k_shadows) && scene.lift_shadow_origins)
          point.shadow_from = lifted_point(scene, tri, hit, p, geometric);
    }
  }
  return point;
}
// [/listing:shading_point]

// Whether a light reaches the surface: always without shadows, else when the shadow ray from
// `origin` along `to_light` meets nothing before tmax (where the light is).
// [listing:light_reaches]
template <class T, class F, class S>
RT_HD bool light_reaches(const S& scene, Vec3<T> origin, Vec3<T> to_light, T tmax,
                         Vec3<T> geometric, F features, ShadedSample<T>& sample) {
  if constexpr (F::compiled(k_shadows)) {
    if (features.on(k_shadows)) {
      ++sample.shadow_rays;
      if (occluded(scene.mesh, Ray<T>{origin, to_light, T(0), tmax})) {
        if (dot(geometric, to_light) > T(0)) ++sample.shadowed_facing;
        return false;
      }
    }
  }
  return true;
}
// [/listing:light_reaches]

// [listing:direct_light]
// Irradiance at the point: ambient, plus each light that reaches it, weighted by Lambert's
// cosine. Shadow rays start off the surface by chapter 03's scale-aware offset, on the
// viewer's side of the face.
template <class T, class F, class S>
RT_HD Vec3<T> irradiance(const S& scene, const ShadingPoint<T>& point, F features,
                         ShadedSample<T>& sample) {
  const Lights& lights = scene.lights;
  const Vec3<T> p = point.position, n = point.shading;
  const Vec3<T> origin = ch03::offset_ray_origin(point.shadow_from, point.geometric);
  Vec3<T> sum = lights.ambient.template as<T>();
  for (int i = 0; i < lights.directional_count; ++i) {
    const Vec3<T> l = lights.directional[i].direction.template as<T>();
    const T cosine = dot(n, l);
    if (!(cosine > T(0))) continue; // faces away from the light (NaN too)
    if (!light_reaches(scene, origin, l, std::numeric_limits<T>::infinity(), point.geometric,
                       features, sample))
      continue;
    sum += lights.directional[i].radiance.template as<T>() * cosine;
  }
  if constexpr (F::compiled(k_point_lights)) {
    if (features.on(k_point_lights)) {
      for (int i = 0; i < lights.point_count; ++i) {
        const Vec3<T> position = lights.point[i].position.template as<T>();
        const Vec3<T> to_light = position - p;
        const T distance_squared = length_squared(to_light);
        const T cosine = dot(n, to_light / square_root(distance_squared));
        if (!(cosine > T(0))) continue;
        // Direction origin -> light, so the light sits at t = 1.
        if (!light_reaches(scene, origin, position - origin, T(1), point.geometric, features,
                           sample))
          continue;
        sum += lights.point[i].intensity.template as<T>() * (cosine / distance_squared);
      }
    }
  }
  return sum;
}
// [/listing:direct_light]

// [listing:shade_ray]
template <class T, class F, class S>
RT_HD ShadedSample<T> shade_ray(const S& scene, const Ray<T>& ray, F features) {
  ShadedSample<T> sample;
  const Vec3<T> d = normalize(ray.direction);
  const SurfaceHit<T> hit = closest_surface(scene.mesh, ray);
  if (hit.triangle < 0) {
    sample.colour = ch03::sky_colour(d);
    return sample;
  }
  sample.triangle = hit.triangle;
  const ShadingPoint<T> point = shading_point(scene, ray, hit, features);
  const Vec3<T> albedo = scene.palette.albedo[scene.material[hit.triangle]].template as<T>();
  sample.colour = albedo * irradiance(scene, point, features, sample); // Lambert
  return sample;
}
// [/listing:shade_ray]

} // namespace rt::ch06
