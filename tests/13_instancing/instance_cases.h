// Chapter 13 tests: what the CPU and GPU tests share. Random transforms in the supported
// range, random rays through a scene's box, and a scene's hits compared bit for bit.
#pragma once

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "instance.h"
#include "instance_scene.h"

namespace rt::ch13::testing {

// Same bytes: the bit-for-bit comparison (a float compare would call -0 and +0 equal and NaN
// different from itself).
template <class T> bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// A number between lo and hi, evenly spread in its logarithm (scales over six decades).
inline double log_uniform(std::mt19937& random, double lo, double hi) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  return lo * std::pow(hi / lo, unit(random));
}

inline Vec3d random_unit_vector(std::mt19937& random) {
  std::normal_distribution<double> normal(0.0, 1.0);
  for (;;) {
    const Vec3d v{normal(random), normal(random), normal(random)};
    const double l = std::sqrt(dot(v, v));
    if (l > 1e-3) return v / l;
  }
}

// translation * rotation * scaling: a random axis and angle, each axis scaled within
// [scale_lo, scale_hi] (log-uniform), the translation anywhere within `reach` on each axis. A
// rotation's columns are unit only to rounding, so the scales keep a hair inside the bounds.
inline AffineD random_transform(std::mt19937& random, double scale_lo, double scale_hi,
                                double reach) {
  scale_lo *= 1.0 + 1e-9;
  scale_hi *= 1.0 - 1e-9;
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi),
      offset(-reach, reach);
  const Vec3d s{log_uniform(random, scale_lo, scale_hi),
                log_uniform(random, scale_lo, scale_hi),
                log_uniform(random, scale_lo, scale_hi)};
  return translation({offset(random), offset(random), offset(random)}) *
         rotation(random_unit_vector(random), angle(random)) * scaling(s);
}

// A point of the box, uniformly.
inline Vec3f random_point_in(std::mt19937& random, const ch07::Aabb& box) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  return {box.lo.x + (box.hi.x - box.lo.x) * unit(random),
          box.lo.y + (box.hi.y - box.lo.y) * unit(random),
          box.lo.z + (box.hi.z - box.lo.z) * unit(random)};
}

// `count` rays from random points of `box` widened by `margin` of its size on every side,
// each aimed at a random point inside `box`.
inline std::vector<RayF> rays_into_box(const ch07::Aabb& box, double margin, int count,
                                       unsigned seed) {
  std::mt19937 random(seed);
  const Vec3f size = box.hi - box.lo;
  ch07::Aabb around = box;
  around.lo = box.lo - size * float(margin);
  around.hi = box.hi + size * float(margin);
  std::vector<RayF> rays;
  while (static_cast<int>(rays.size()) < count) {
    const Vec3f origin = random_point_in(random, around);
    const Vec3f target = random_point_in(random, box);
    if (target == origin) continue;
    rays.push_back({origin, target - origin});
  }
  return rays;
}

// The box around every vertex of the scene flattened (placed in double, rounded to float).
inline ch07::Aabb scene_box(const InstanceScene& scene) {
  ch07::Aabb box;
  for (const Placement& p : scene.placements)
    for (const Vec3f& v : scene.meshes[p.mesh].vertices)
      box.grow(p.to_world.point(v.as<double>()).as<float>());
  return box;
}

// A forest of `count` icospheres of 80 triangles on a ground, as the program's --small makes
// (with fewer triangles, so that brute force stays quick), turning at `speed`.
inline Forest icosphere_forest(int count, unsigned seed, double speed) {
  return make_forest(ch04::make_icosphere(1, {0.0, 1.0, 0.0}, 1.0), count, seed, speed);
}

} // namespace rt::ch13::testing
