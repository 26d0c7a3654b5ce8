// Chapter 07: chapter 06's shading, traced through the tree. The shading code is unchanged;
// it calls closest_surface, occluded and triangle_as on the scene's geometry, and for a
// BvhGeometry those are the functions below. In float they walk the tree; the float64
// reference has no tree of its own and tests every triangle, as in chapter 06.
#pragma once

#include <type_traits>

#include "shade.h"
#include "traverse.h"

namespace rt::ch07 {

// The geometry a shaded scene traces: a tree (BvhView, or any type the traversal accepts, as
// in chapter 08) and the mesh it was built from.
template <class Tree> struct BvhGeometryOf {
  Tree bvh;            // the tree and its leaf-ordered triangle copies
  ch04::MeshView mesh; // the mesh itself, by the mesh's triangle numbers (for shading)
};

using BvhGeometry = BvhGeometryOf<BvhView>;
using BvhSceneView = ch06::SceneViewOf<BvhGeometry>;

// [listing:bvh_geometry]
template <class T, class Tree>
RT_HD ch06::SurfaceHit<T> closest_surface(const BvhGeometryOf<Tree>& g,
                                          const ch03::Ray<T>& ray) {
  if constexpr (std::is_same_v<T, float>) {
    const TraceHit hit = trace_bvh<Query::closest, TriangleVariant::watertight>(g.bvh, ray);
    return {hit.t, hit.triangle, hit.u, hit.v};
  } else {
    return ch06::closest_surface(g.mesh, ray);
  }
}

template <class T, class Tree>
RT_HD bool occluded(const BvhGeometryOf<Tree>& g, const ch03::Ray<T>& ray) {
  if constexpr (std::is_same_v<T, float>)
    return trace_bvh<Query::any, TriangleVariant::watertight>(g.bvh, ray).triangle >= 0;
  else
    return ch06::occluded(g.mesh, ray);
}
// [/listing:bvh_geometry]

template <class T, class Tree>
RT_HD ch04::Triangle<T> triangle_as(const BvhGeometryOf<Tree>& g, int i) {
  return ch06::triangle_as<T>(g.mesh, i);
}

// Chapter 06's scene view with the tree added.
template <class Tree>
ch06::SceneViewOf<BvhGeometryOf<Tree>> with_bvh(const ch06::SceneView& scene, const Tree& bvh) {
  return {{bvh, scene.mesh},        scene.material, scene.normals,
          scene.normal_indices,     scene.palette,  scene.lights,
          scene.lift_shadow_origins};
}

} // namespace rt::ch07
