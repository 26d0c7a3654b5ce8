// Chapter 07's meshes and rays for spatial splits, shared by its sbvh tests and by chapter
// 09's (wide trees collapsed from sbvh trees): long thin triangles across a scene, a closed
// tube of them, and the rays aimed where a careless clip would end short of a triangle.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "bvh.h"
#include "camera_spec.h"
#include "mesh_gen.h"

namespace rt::testing {

using ch03::RayF;

// Long thin triangles across the whole scene, in random directions: each one's box is nearly
// the scene's, which no object split can shrink. Spatial splits were made for them.
inline ch04::Mesh long_slivers(int count, unsigned seed, float extent = 10.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> where(-0.5f * extent, 0.5f * extent);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  ch04::Mesh mesh;
  for (int i = 0; i < count; ++i) {
    const Vec3f p{where(rng), where(rng), where(rng)}, q{where(rng), where(rng), where(rng)};
    const Vec3f side = Vec3f{unit(rng), unit(rng), unit(rng)} * (0.002f * extent);
    const int base = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(p);
    mesh.vertices.push_back(q);
    mesh.vertices.push_back(0.5f * p + 0.5f * q + side);
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

// A closed tube of long thin triangles along the diagonal (1, 1, 1), capped by fans: a mesh
// rays must not leak out of, made of just the triangles spatial splits cut.
inline ch04::Mesh diagonal_tube(Vec3d centre, int sides = 24, double length = 20.0,
                                double radius = 1.0) {
  const Vec3d axis = Vec3d{1.0, 1.0, 1.0} * (1.0 / std::sqrt(3.0));
  const Vec3d u = Vec3d{1.0, -1.0, 0.0} * (1.0 / std::sqrt(2.0));
  const Vec3d w = cross(axis, u);
  ch04::Mesh mesh;
  for (int end = 0; end < 2; ++end) {
    const Vec3d middle = centre + axis * ((end - 0.5) * length);
    for (int k = 0; k < sides; ++k) {
      const double angle = 2.0 * 3.14159265358979323846 * k / sides;
      mesh.vertices.push_back(
          (middle + (u * std::cos(angle) + w * std::sin(angle)) * radius).as<float>());
    }
    mesh.vertices.push_back(middle.as<float>());
  }
  const int second = sides + 1; // the first vertex of the far ring
  for (int k = 0; k < sides; ++k) {
    const int next = (k + 1) % sides;
    mesh.triangles.push_back({k, next, second + k});
    mesh.triangles.push_back({next, second + next, second + k});
    mesh.triangles.push_back({sides, next, k});                            // near cap
    mesh.triangles.push_back({second + sides, second + k, second + next}); // far cap
  }
  return mesh;
}

// The rays a careless clip lets through: from around `inside` at every point where an edge of
// a leaf's triangle crosses a face of that leaf's box. These are the corners of the clipped
// parts, where a box rounded the wrong way ends short of the triangle.
inline std::vector<RayF> rays_at_clip_corners(const ch07::Bvh& bvh, Vec3f inside,
                                              unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-0.3f, 0.3f);
  std::vector<RayF> rays;
  for (const ch07::BvhNode& node : bvh.nodes) {
    for (int c = 0; c < 2; ++c) {
      for (int k = node.first[c]; k < node.first[c] + node.count[c]; ++k) {
        const ch04::TriangleF& t = bvh.triangles[k];
        const Vec3d v[3] = {t.v0.as<double>(), t.v1.as<double>(), t.v2.as<double>()};
        for (int axis = 0; axis < 3; ++axis) {
          for (const double plane :
               {double(node.box[c].lo[axis]), double(node.box[c].hi[axis])}) {
            for (int e = 0; e < 3; ++e) {
              const Vec3d a = v[e], b = v[(e + 1) % 3];
              if (!((a[axis] < plane && plane < b[axis]) ||
                    (b[axis] < plane && plane < a[axis])))
                continue;
              const Vec3f target =
                  (a + (b - a) * ((plane - a[axis]) / (b[axis] - a[axis]))).as<float>();
              for (int r = 0; r < 3; ++r) {
                const Vec3f origin = inside + Vec3f{unit(rng), unit(rng), unit(rng)};
                rays.push_back(RayF{origin, target - origin});
              }
            }
          }
        }
      }
    }
  }
  return rays;
}

} // namespace rt::testing
