// Chapter 10 test cases shared by its test files: the meshes that stress a Morton-code build
// (every centroid equal; points spaced by powers of two) and a clustering one (centroids on a
// line, evenly or ever wider spaced), a mesh bent out of shape for the refit, and the
// comparison of a tree's hits with brute force.
#pragma once

#include <cmath>
#include <vector>

#include "07_bvh/bvh_cases.h"
#include "mesh_gen.h"
#include "traverse.h"
#include "triangles.h"

namespace rt::ch10::testing {

using ch03::RayF;
using ch04::Mesh;

// A flat triangle at one point: its box and centroid are that point exactly.
inline void add_point_triangle(Mesh& mesh, Vec3f p) {
  const int base = static_cast<int>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), {p, p, p});
  mesh.triangles.push_back({base, base + 1, base + 2});
}

// A soup spread over almost the whole float range: float areas overflow to infinity, and a
// flat box's inf * 0 is NaN.
inline Mesh huge_soup() {
  Mesh mesh = rt::testing::random_soup(2000, 61, {{}, 1e38f, 1e35f, 1e37f});
  for (int k = 0; k < 20; ++k) add_point_triangle(mesh, {float(k) * 1e37f, 0.0f, 0.0f});
  return mesh;
}

// `count` copies of one small triangle: every centroid and every code equal.
inline Mesh identical_triangles(int count) {
  Mesh mesh;
  mesh.vertices = {{0.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 1.0f}, {0.0f, 1.0f, 1.0f}};
  for (int i = 0; i < count; ++i) mesh.triangles.push_back({0, 1, 2});
  return mesh;
}

// Points at 2^-k along each axis in turn (k = 1 .. 21), one at (1, 1, 1) and `pile` at the
// origin. Each power of two is a code with a single bit set, so the sorted codes peel off one
// leaf per level: a chain as long as the code has bits, with the pile's subtree below it.
inline Mesh power_of_two_chain(int pile) {
  Mesh mesh;
  for (int i = 0; i < pile; ++i) add_point_triangle(mesh, {0.0f, 0.0f, 0.0f});
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 1; k <= 21; ++k) {
      Vec3f p{0.0f, 0.0f, 0.0f};
      (axis == 0 ? p.x : axis == 1 ? p.y : p.z) = std::ldexp(1.0f, -k);
      add_point_triangle(mesh, p);
    }
  add_point_triangle(mesh, {1.0f, 1.0f, 1.0f});
  return mesh;
}

// One small triangle in the plane x = p, a unit square's half: its box is flat in x.
inline void add_triangle_at_x(Mesh& mesh, float x) {
  const int base = static_cast<int>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(),
                       {{x, 0.0f, 0.0f}, {x, 1.0f, 0.0f}, {x, 0.0f, 1.0f}});
  mesh.triangles.push_back({base, base + 1, base + 2});
}

// `count` triangles at x = 0, 1, 2, ...: centroids on a line, evenly spaced, so that every
// cluster's two nearest neighbours are equally near. Made in x order, which the Morton order
// keeps (equal codes stay in number order).
inline Mesh collinear_triangles(int count) {
  Mesh mesh;
  for (int k = 0; k < count; ++k) add_triangle_at_x(mesh, static_cast<float>(k));
  return mesh;
}

// `count` (at most 500) triangles at x = 2^(k/4): centroids spaced ever wider, so that every
// cluster's nearest neighbour is its left one, in every round: a chain whose only mutual pair
// is its first two. Made in x order, which the Morton order keeps.
inline Mesh exponentially_spaced_triangles(int count) {
  Mesh mesh;
  for (int k = 0; k < count; ++k) add_triangle_at_x(mesh, std::exp2(0.25f * k));
  return mesh;
}

// The mesh with every vertex moved by a smooth wave: the same triangles, new positions.
inline Mesh bent(const Mesh& mesh, float amount) {
  Mesh moved = mesh;
  for (Vec3f& v : moved.vertices)
    v = v + Vec3f{std::sin(v.y * 1.3f), std::cos(v.z * 0.7f), std::sin(v.x + v.y)} * amount;
  return moved;
}

// Rays whose closest hit through the tree differs from brute force's (ties, another triangle
// at exactly the same distance, allowed), and whose any-hit occlusion differs.
template <class Tree>
int brute_force_mismatches(const Tree& tree, const Mesh& mesh, const std::vector<RayF>& rays) {
  constexpr ch04::TriangleVariant k_watertight = ch04::TriangleVariant::watertight;
  const ch04::MeshView view = ch04::host_view(mesh);
  int mismatches = 0;
  for (const RayF& ray : rays) {
    const ch04::MeshHit brute = ch04::closest_hit(k_watertight, view, ray);
    const ch07::TraceHit closest =
        ch07::trace_bvh<ch07::Query::closest, k_watertight>(tree, ray);
    const bool same_miss = brute.triangle < 0 && closest.triangle < 0;
    const bool same_t = brute.triangle >= 0 && closest.triangle >= 0 && brute.t == closest.t;
    if (!same_miss && !same_t) ++mismatches;
    const bool occluded =
        ch07::trace_bvh<ch07::Query::any, k_watertight>(tree, ray).triangle >= 0;
    if (occluded != (brute.triangle >= 0)) ++mismatches;
  }
  return mismatches;
}

} // namespace rt::ch10::testing
