// Chapter 09's test cases, shared by its test files: scenes (a soup with a closed sphere and a
// grid box, far from the origin too, and the degenerate ones), rays (random, aimed at vertices
// and edges, along box faces, and the hostile ones that must miss), every wide tree of a mesh,
// and the comparisons against brute force and chapter 07.
#pragma once

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "07_bvh/bvh_cases.h"
#include "bvh_build.h"
#include "collapse.h"
#include "cpu_traverse.h"
#include "shaded_scene.h"
#include "traverse.h"
#include "wide_traverse.h"

namespace rt::ch09::testing {

using ch04::Mesh;
using ch04::MeshHit;

inline constexpr float k_inf = std::numeric_limits<float>::infinity();

// Chapter 07's soup of triangles of mixed sizes around a centre.
using rt::testing::random_soup;

// The soup with a closed sphere and a grid box in it (flat node boxes, faces on slab planes),
// all moved by `offset`.
inline Mesh mixed_scene(int soup, unsigned seed, Vec3f offset = {}) {
  Mesh scene = random_soup(soup, seed, offset);
  const Vec3d o = offset.as<double>();
  ch04::append_mesh(scene, ch04::make_icosphere(3, o + Vec3d{2.0, 0.5, -1.0}, 2.0));
  ch04::append_mesh(scene,
                    ch04::make_box(o + Vec3d{-4.0, -4.0, -4.0}, o + Vec3d{-2.0, -1.0, 3.0}, 4));
  return scene;
}

// Triangles growing geometrically along x, from x = 1 by a factor of 1.3, `count` of them:
// chapter 07's binned SAH can only peel the largest one or two off at each level, so its tree
// is as deep as its depth bound lets it be. Returns the chain; `far` gets the last x.
inline Mesh geometric_chain(int count, float& far) {
  Mesh chain;
  float x = 1.0f;
  for (int i = 0; i < count; ++i, x *= 1.3f) {
    const int base = static_cast<int>(chain.vertices.size());
    const float s = 0.2f * x;
    chain.vertices.push_back({x - s, -s, 0.0f});
    chain.vertices.push_back({x + s, -s, 0.1f * s});
    chain.vertices.push_back({x, s, -0.1f * s});
    chain.triangles.push_back({base, base + 1, base + 2});
  }
  far = x;
  return chain;
}

// Random rays through the scene around `centre` (some with a finite tmax or a tmin), rays aimed
// at triangles' centroids, vertices and edge midpoints, rays along the grid box's faces (for a
// mixed_scene around `centre`), and the hostile rays that must miss at once.
inline std::vector<RayF> rays_for(const Mesh& mesh, int random_count, unsigned seed,
                                  Vec3f centre = {}) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<RayF> rays;
  for (int i = 0; i < random_count; ++i) {
    const float reach = (i % 4 == 0) ? 4.0f : 12.0f;
    const Vec3f o = centre + Vec3f{unit(rng), unit(rng), unit(rng)} * reach;
    const Vec3f target = centre + Vec3f{unit(rng), unit(rng), unit(rng)} * 3.0f;
    RayF ray{o, target - o};
    if (i % 5 == 0) ray.tmax = 0.5f + 0.5f * unit(rng);
    if (i % 7 == 0) ray.tmin = 0.1f;
    rays.push_back(ray);
  }
  const int aimed = std::min<int>(static_cast<int>(mesh.triangles.size()), 400);
  for (int k = 0; k < aimed; ++k) {
    const auto& t = mesh.triangles[(k * 7919) % mesh.triangles.size()];
    const Vec3f a = mesh.vertices[t.v0], b = mesh.vertices[t.v1], c = mesh.vertices[t.v2];
    const Vec3f o = centre + Vec3f{unit(rng), unit(rng), unit(rng)} * 12.0f;
    for (const Vec3f target : {(a + b + c) / 3.0f, a, (a + b) * 0.5f})
      rays.push_back({o, target - o});
  }
  for (int a = 0; a <= 8; ++a) // along and onto the faces of the box (-4,-4,-4)..(-2,-1,3)
    for (int b = 0; b <= 8; ++b) {
      const float u = -4.0f + 0.25f * a, v = -4.0f + 0.875f * b;
      rays.push_back({centre + Vec3f{u, -1.0f, -9.0f}, {0.0f, 0.0f, 1.0f}});
      rays.push_back({centre + Vec3f{u, v, 9.0f}, {-0.0f, -0.0f, -1.0f}});
      rays.push_back({centre + Vec3f{-4.0f, u + 1.0f, v}, {0.0f, 1.0f, 0.0f}});
      rays.push_back({centre + Vec3f{-9.0f, v * 0.375f, u}, {1.0f, 0.0f, 0.0f}});
    }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  rays.push_back({{nan, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}});
  rays.push_back({{0.0f, 0.0f, -20.0f}, {0.0f, nan, 1.0f}});
  rays.push_back({{k_inf, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f}});
  rays.push_back({{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, k_inf}});
  rays.push_back({{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 0.0f}});
  rays.push_back({{0.0f, 0.0f, -20.0f}, {-0.0f, 0.0f, -0.0f}});
  rays.push_back({{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 1.0f}, nan, k_inf});
  rays.push_back({{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, nan});
  const float tiny = std::numeric_limits<float>::denorm_min();
  rays.push_back({centre + Vec3f{0.5f, 0.5f, -20.0f}, {tiny, -tiny, 1.0f}});
  rays.push_back({centre + Vec3f{1e6f, 0.1f, 0.2f}, {-1.0f, 0.0f, 0.0f}}); // from far away
  return rays;
}

// Every wide tree of a mesh: each stored layout of each collapse.
struct WideTrees {
  Wide4Bvh wide4_sah, wide4_greedy;
  Wide8Bvh wide8_sah, wide8_greedy;
  CompressedBvh compressed_sah, compressed_greedy;
  Wide4PackedBvh wide4_packed; // the SAH collapse, triangles in 40-byte records
};

inline WideTrees all_wide_trees(const Mesh& mesh) {
  const WideLayout sah4 = build_wide_layout(mesh, 4, Collapse::sah);
  const WideLayout greedy4 = build_wide_layout(mesh, 4, Collapse::greedy);
  const WideLayout sah8 = build_wide_layout(mesh, 8, Collapse::sah);
  const WideLayout greedy8 = build_wide_layout(mesh, 8, Collapse::greedy);
  return {pack_wide<4>(sah4),
          pack_wide<4>(greedy4),
          pack_wide<8>(sah8),
          pack_wide<8>(greedy8),
          compress(sah8),
          compress(greedy8),
          pack_wide<4, PackedTriangles>(sah4)};
}

// Calls fn(name, view) for each tree of `trees`.
template <class Fn> void for_each_tree(const WideTrees& trees, Fn fn) {
  fn("wide4 sah", trees.wide4_sah.view());
  fn("wide4 greedy", trees.wide4_greedy.view());
  fn("wide8 sah", trees.wide8_sah.view());
  fn("wide8 greedy", trees.wide8_greedy.view());
  fn("cwbvh8 sah", trees.compressed_sah.view());
  fn("cwbvh8 greedy", trees.compressed_greedy.view());
  fn("wide4 packed", trees.wide4_packed.view());
}

template <Query kQuery, class Tree, class C = ch07::NoCounters>
TraceHit trace(const Tree& tree, const RayF& ray, C&& counters = C{}) {
  return trace_wide<kQuery>(tree, ray, counters);
}
// The CPU's own tree through its own traversal (cpu_traverse.h).
template <Query kQuery, class C = ch07::NoCounters>
TraceHit trace(const CpuTreeView& tree, const RayF& ray, C&& counters = C{}) {
  return trace_cpu<kQuery>(tree, ray, counters);
}

// How a tree's answers relate to brute force's (chapter 04, watertight): closest hits the
// same up to exact ties (another triangle at exactly the same t), any hits the same occlusion,
// and every any hit a real hit of its triangle.
struct Agreement {
  int closest_mismatches = 0;
  int ties = 0;
  int any_mismatches = 0;
  int hits = 0;
};

template <class Tree>
Agreement against_brute_force(const Tree& tree, const Mesh& mesh,
                              const std::vector<RayF>& rays) {
  const ch04::MeshView view = ch04::host_view(mesh);
  constexpr ch04::TriangleVariant k_watertight = ch04::TriangleVariant::watertight;
  Agreement a;
  for (const RayF& ray : rays) {
    const MeshHit brute = ch04::closest_hit(k_watertight, view, ray);
    const TraceHit closest = trace<Query::closest>(tree, ray);
    if (brute.triangle >= 0) ++a.hits;
    if (!(closest.triangle == brute.triangle && (brute.triangle < 0 || closest.t == brute.t))) {
      if (brute.triangle >= 0 && closest.triangle >= 0 && closest.t == brute.t)
        ++a.ties;
      else
        ++a.closest_mismatches;
    }
    const TraceHit any = trace<Query::any>(tree, ray);
    if ((any.triangle >= 0) != (brute.triangle >= 0)) ++a.any_mismatches;
    if (any.triangle >= 0) {
      const auto h = ch04::intersect_triangle(k_watertight, ray, mesh.triangle(any.triangle));
      if (!h.hit || h.t != any.t) ++a.any_mismatches;
    }
  }
  return a;
}

// The picture tests' view: chapter 06's default scene, its compressed tree, and the default
// camera at 96 x 54.
struct ShadedView {
  ch06::ShadedScene scene = ch06::make_default_scene(2, 1.0, {});
  CompressedBvh tree = compress(build_wide_layout(scene.mesh, 8, Collapse::sah));
  Extent extent{96, 54};
  ch03::Camera<float> camera = ch03::make_camera<float>(ch06::default_camera(1.0), extent);
};

} // namespace rt::ch09::testing
