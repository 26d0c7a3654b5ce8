// Chapter 07 test cases shared by its build, traversal, protocol and GPU tests and by chapter
// 08's: build options, random triangle soups and the scenes made with them, random rays, the
// hostile rays every traversal must refuse at once, and bit-for-bit comparisons.
#pragma once

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "bvh_build.h"
#include "camera_spec.h"
#include "mesh_gen.h"
#include "shaded_scene.h"
#include "triangles.h"

namespace rt::testing {

using ch03::RayF;

inline ch07::BuildOptions options_of(ch07::SplitMethod method, int max_leaf_size,
                                     int bins = ch07::BuildOptions{}.bins) {
  ch07::BuildOptions options;
  options.method = method;
  options.max_leaf_size = max_leaf_size;
  options.bins = bins;
  return options;
}

// Bit-for-bit equality: == would call -0 and 0 equal and NaN unequal to itself.
template <class T> bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class T> bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

inline long long count_hits(const std::vector<ch04::MeshHit>& hits) {
  return std::count_if(hits.begin(), hits.end(),
                       [](const ch04::MeshHit& h) { return h.triangle >= 0; });
}

// ---------------------------------------------------------------------------------------------
// Scenes.

// Where a random soup lies and how large its triangles are: each triangle's centre is uniform
// in the cube `centre` +- `half_side`, and its vertices lie within +-size of that centre on
// every axis, the size uniform in [smallest, largest).
struct SoupLayout {
  Vec3f centre;
  float half_side;
  float smallest;
  float largest;
};

inline ch04::Mesh random_soup(int count, unsigned seed, const SoupLayout& layout) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> where(-layout.half_side, layout.half_side);
  std::uniform_real_distribution<float> size(layout.smallest, layout.largest);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  ch04::Mesh mesh;
  for (int i = 0; i < count; ++i) {
    const Vec3f c = layout.centre + Vec3f{where(rng), where(rng), where(rng)};
    const float s = size(rng);
    const int base = static_cast<int>(mesh.vertices.size());
    for (int k = 0; k < 3; ++k)
      mesh.vertices.push_back(c + Vec3f{unit(rng), unit(rng), unit(rng)} * s);
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

// A soup of triangles of mixed sizes (0.1% to 8% of the side) in a box of side `extent` around
// `centre`.
inline ch04::Mesh random_soup(int count, unsigned seed, Vec3f centre = {},
                              float extent = 10.0f) {
  return random_soup(count, seed, {centre, 0.5f * extent, 0.001f * extent, 0.08f * extent});
}

// The soup with a closed sphere and a grid box in it: flat node boxes, faces on slab planes.
inline ch04::Mesh mixed_scene(int soup, unsigned seed) {
  ch04::Mesh scene = random_soup(soup, seed);
  ch04::append_mesh(scene, ch04::make_icosphere(3, {2.0, 0.5, -1.0}, 2.0));
  ch04::append_mesh(scene, ch04::make_box({-4.0, -4.0, -4.0}, {-2.0, -1.0, 3.0}, 4));
  return scene;
}

// A closed sphere over a flat grid box whose top face is the plane y = -1.5: the GPU tests'
// scene, which rays_towards_origin() aims at.
inline ch04::Mesh sphere_over_box() {
  ch04::Mesh mesh = ch04::make_icosphere(4, {0.5, 0.0, -0.5}, 1.5);
  ch04::append_mesh(mesh, ch04::make_box({-3.0, -2.0, -3.0}, {3.0, -1.5, 3.0}, 8));
  return mesh;
}

// One triangle in the plane z = 3 around the z axis: the ray from the origin along +z meets it
// at t = 3.
inline ch04::Mesh single_triangle() {
  ch04::Mesh one;
  one.vertices = {{-1.0f, -1.0f, 3.0f}, {1.0f, -1.0f, 3.0f}, {0.0f, 1.0f, 3.0f}};
  one.triangles = {{0, 1, 2}};
  return one;
}

// Chapter 06's default scene and its tree, seen through chapter 06's default camera: the
// shaded frame chapters 07 and 08 trace through the tree.
struct ShadedTreeCase {
  ch06::ShadedScene scene;
  ch07::Bvh bvh;
  Extent extent;
  ch03::Camera<float> camera;
};

inline ShadedTreeCase shaded_tree_case(int sphere_subdivisions, Extent extent) {
  ch06::ShadedScene scene = ch06::make_default_scene(sphere_subdivisions, 1.0, {});
  ch07::Bvh bvh = ch07::build_bvh(scene.mesh, {});
  return {std::move(scene), std::move(bvh), extent,
          ch03::make_camera<float>(ch06::default_camera(1.0), extent)};
}

// ---------------------------------------------------------------------------------------------
// Rays.

// Rays from around the scene through it, plus some from inside; a few with a finite tmax or a
// tmin. They start in the cube `centre` +- 1.2 `extent` (every fourth within 0.4 `extent`) and
// pass through a point within 0.3 `extent` of `centre`; every fifth ends between t = 0 and 1,
// every seventh starts at t = 0.1.
inline std::vector<RayF> random_rays(std::mt19937& rng, int count, Vec3f centre, float extent) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<RayF> rays;
  for (int i = 0; i < count; ++i) {
    const float reach = (i % 4 == 0) ? 0.4f * extent : 1.2f * extent;
    const Vec3f o = centre + Vec3f{unit(rng), unit(rng), unit(rng)} * reach;
    const Vec3f target = centre + Vec3f{unit(rng), unit(rng), unit(rng)} * (0.3f * extent);
    RayF ray{o, target - o};
    if (i % 5 == 0) ray.tmax = 0.5f + 0.5f * unit(rng);
    if (i % 7 == 0) ray.tmin = 0.1f;
    rays.push_back(ray);
  }
  return rays;
}

inline std::vector<RayF> random_rays(int count, unsigned seed, Vec3f centre, float extent) {
  std::mt19937 rng(seed);
  return random_rays(rng, count, centre, extent);
}

// Whether random rays all keep the whole interval [0, inf), or some end early and some start
// late.
enum class Intervals { whole, some_finite };

// Rays from the cube [-4, 4]^3 that pass, at t = 4, within 2 of the origin on every axis: into
// sphere_over_box(). With Intervals::some_finite every fifth ends between t = 1 and 3 and every
// seventh starts at t = 0.5.
inline std::vector<RayF> rays_towards_origin(std::mt19937& rng, int count,
                                             Intervals intervals) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<RayF> rays;
  for (int i = 0; i < count; ++i) {
    const Vec3f o{4.0f * unit(rng), 4.0f * unit(rng), 4.0f * unit(rng)};
    RayF ray{o, Vec3f{unit(rng), unit(rng), unit(rng)} * 0.5f - o * 0.25f};
    if (intervals == Intervals::some_finite) {
      if (i % 5 == 0) ray.tmax = 2.0f + unit(rng);
      if (i % 7 == 0) ray.tmin = 0.5f;
    }
    rays.push_back(ray);
  }
  return rays;
}

// Rays with one bad number each, which a traversal must refuse before it reads a node: NaN or
// infinity in the origin, the direction or the interval, and a zero direction. Those with a
// finite origin start at `origin`; the two whose only fault is their interval go along
// `direction`, towards the scene.
inline std::vector<RayF> hostile_rays(Vec3f origin = {0.0f, 0.0f, -20.0f},
                                      Vec3f direction = {0.0f, 0.0f, 1.0f}) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  return {
      {{nan, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}},
      {origin, {0.0f, nan, 1.0f}},
      {{inf, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f}},
      {origin, {0.0f, 0.0f, inf}},
      {origin, {0.0f, 0.0f, 0.0f}}, // no direction
      {origin, direction, nan, inf},
      {origin, direction, 0.0f, nan},
  };
}

} // namespace rt::testing
