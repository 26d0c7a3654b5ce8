// Chapter 07: chapter 06's shading, traced through the tree. The shading code is unchanged;
// it calls closest_surface, occluded and triangle_as on the scene's geometry, and for a
// BvhGeometry those are the functions below. In float they walk the tree; the float64
// reference has no tree of its own and tests every triangle, as in chapter 06.
#pragma once

#include <type_traits>

#include "shade.h"
#include "traverse.h"

namespace rt::ch07 {

struct BvhGeometry {
  BvhView bvh;         // the tree and its leaf-ordered triangle copies
  ch04::MeshView mesh; // the mesh itself, by the mesh's triangle numbers (for shading)
};

using BvhSceneView = ch06::SceneViewOf<BvhGeometry>;

// [listing:bvh_geometry]
template <class T>
RT_HD ch06::SurfaceHit<T> closest_surface(const BvhGeometry& g, const ch03::Ray<T>& ray) {
  if constexpr (std::is_same_v<T, float>) {
    const TraceHit hit = trace_bvh<Query::closest, TriangleVariant::watertight>(g.bvh, ray);
    return {hit.t, hit.triangle, hit.u, hit.v};
  } else {
    return ch06::closest_surface(g.mesh, ray);
  }
}

template <class T> RT_HD bool occluded(const BvhGeometry& g, const ch03::Ray<T>& ray) {
  if constexpr (std::is_same_v<T, float>)
    return trace_bvh<Query::any, TriangleVariant::watertight>(g.bvh, ray).triangle >= 0;
  else
    return ch06::occluded(g.mesh, ray);
}
// [/listing:bvh_geometry]

template <class T> RT_HD ch04::Triangle<T> triangle_as(const BvhGeometry& g, int i) {
  return ch06::triangle_as<T>(g.mesh, i);
}

// Chapter 06's scene view with the tree added.
inline BvhSceneView with_bvh(const ch06::SceneView& scene, const BvhView& bvh) {
  return {{bvh, scene.mesh},    scene.material, scene.normals,
          scene.normal_indices, scene.palette,  scene.lights};
}

} // namespace rt::ch07
