// Chapter 09: chapter 06's shading traced through a wide tree, as chapter 07 traced it through
// the binary one: the shading code is unchanged, and for a WideGeometryOf its closest_surface
// and occluded are the functions below. The float64 reference still tests every triangle.
#pragma once

#include <type_traits>

#include "shade.h"
#include "wide_traverse.h"

namespace rt::ch09 {

template <class Tree> struct WideGeometryOf {
  Tree tree;           // the wide tree and its leaf-ordered triangle records
  ch04::MeshView mesh; // the mesh itself, by the mesh's triangle numbers (for shading)
};

template <class T, class Tree>
RT_HD ch06::SurfaceHit<T> closest_surface(const WideGeometryOf<Tree>& g,
                                          const ch03::Ray<T>& ray) {
  if constexpr (std::is_same_v<T, float>) {
    const TraceHit hit = trace_wide<Query::closest>(g.tree, ray);
    return {hit.t, hit.triangle, hit.u, hit.v};
  } else {
    return ch06::closest_surface(g.mesh, ray);
  }
}

template <class T, class Tree>
RT_HD bool occluded(const WideGeometryOf<Tree>& g, const ch03::Ray<T>& ray) {
  if constexpr (std::is_same_v<T, float>)
    return trace_wide<Query::any>(g.tree, ray).triangle >= 0;
  else
    return ch06::occluded(g.mesh, ray);
}

template <class T, class Tree>
RT_HD ch04::Triangle<T> triangle_as(const WideGeometryOf<Tree>& g, int i) {
  return ch06::triangle_as<T>(g.mesh, i);
}

// The image's tree: the compressed one; and the 4-wide packed one, which chapter 10 builds
// on the GPU.
template <class Tree> using WideSceneViewOf = ch06::SceneViewOf<WideGeometryOf<Tree>>;
using CompressedSceneView = WideSceneViewOf<WideTreeView<CompressedNode>>;
using Wide4PackedSceneView = WideSceneViewOf<Wide4PackedBvh::View>;

// Chapter 06's scene view with the tree added.
template <class Tree>
WideSceneViewOf<Tree> with_wide(const ch06::SceneView& scene, const Tree& tree) {
  return {{tree, scene.mesh},   scene.material, scene.normals,
          scene.normal_indices, scene.palette,  scene.lights};
}

} // namespace rt::ch09
