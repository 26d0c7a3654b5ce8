// Chapter 13: an instance, a mesh placed in the world by an affine transform. The ray goes to
// the mesh's own space at the instance (the inverse transform), meets the mesh's tree there,
// and comes back with its hit: the instance, the mesh's triangle and t. The direction is
// transformed but not normalised, so t means the same along both rays and needs no converting.
#pragma once

#include <limits>
#include <string>

#include "ray.h"
#include "rt/hd.h"
#include "rt/vec.h"

namespace rt::ch13 {

using ch03::RayF;

// [listing:affine]
// A 3 x 4 matrix, row by row: the linear part in columns 0-2, the translation in column 3.
// A point p goes to (row_r . p) + m[r][3]; a direction leaves the translation out.
struct Affine {
  float m[3][4];

  RT_HD Vec3f point(Vec3f p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  RT_HD Vec3f direction(Vec3f d) const {
    return {m[0][0] * d.x + m[0][1] * d.y + m[0][2] * d.z,
            m[1][0] * d.x + m[1][1] * d.y + m[1][2] * d.z,
            m[2][0] * d.x + m[2][1] * d.y + m[2][2] * d.z};
  }
};
// [/listing:affine]

// The same in double, for building, checking and inverting (the host, and the GPU's pass that
// moves instances every frame).
struct AffineD {
  double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

  RT_HD Vec3d point(Vec3d p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  RT_HD Vec3d direction(Vec3d d) const {
    return {m[0][0] * d.x + m[0][1] * d.y + m[0][2] * d.z,
            m[1][0] * d.x + m[1][1] * d.y + m[1][2] * d.z,
            m[2][0] * d.x + m[2][1] * d.y + m[2][2] * d.z};
  }
  RT_HD Affine as_float() const { // every entry rounded to nearest once
    Affine out;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) out.m[r][c] = static_cast<float>(m[r][c]);
    return out;
  }
};

// a after b: (a * b).point(p) == a.point(b.point(p)) up to rounding.
RT_HD inline AffineD operator*(const AffineD& a, const AffineD& b) {
  AffineD out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      out.m[r][c] = a.m[r][0] * b.m[0][c] + a.m[r][1] * b.m[1][c] + a.m[r][2] * b.m[2][c] +
                    (c == 3 ? a.m[r][3] : 0.0);
  return out;
}
AffineD translation(Vec3d t);
AffineD scaling(Vec3d s);
AffineD rotation(Vec3d axis, double radians); // about an axis through the origin

// The determinant of the linear part, and the inverse (the adjugate over the determinant, all
// in double); the caller has checked the transform (check_transform), so the determinant is
// far from zero.
RT_HD inline double determinant(const AffineD& a) {
  const auto& m = a.m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}
RT_HD inline AffineD inverse(const AffineD& a) {
  const auto& m = a.m;
  const double s = 1.0 / determinant(a);
  AffineD inv;
  inv.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * s;
  inv.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * s;
  inv.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * s;
  inv.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * s;
  inv.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * s;
  inv.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * s;
  inv.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * s;
  inv.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * s;
  inv.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * s;
  for (int r = 0; r < 3; ++r)
    inv.m[r][3] = -(inv.m[r][0] * m[0][3] + inv.m[r][1] * m[1][3] + inv.m[r][2] * m[2][3]);
  return inv;
}

// [listing:transform_range]
// What the course accepts as an instance's transform. Its linear part stretches each axis of
// the mesh by the length of the matching column; a length outside [k_min_scale, k_max_scale]
// is refused, as is a transform that flattens the mesh (|det| below k_min_volume_ratio times
// the product of the three lengths: the columns nearly in one plane), one that is not finite,
// and a translation beyond chapter 03's supported coordinates. Within this range the inverse
// loses at most a few digits of float's seven, which the leak tests measure.
inline constexpr double k_min_scale = 1e-3;
inline constexpr double k_max_scale = 1e3;
inline constexpr double k_min_volume_ratio = 1e-6;
// [/listing:transform_range]

// Throws InputError, one line naming `what` and the problem, unless the transform is in range.
void check_transform(const AffineD& a, const std::string& what);

// [listing:instance]
// One placement of a mesh: both directions of its transform (to_object is the inverse of
// to_world, each rounded to float once from the double computation), the mesh's number and a
// mask: a ray tests the instance only where (ray mask & instance mask) != 0.
struct Instance {
  Affine to_world;
  Affine to_object;
  int mesh = 0;
  unsigned mask = 0xffffffffu;
};
// [/listing:instance]

// An instance of `mesh` at `to_world` (already checked): both directions rounded to float.
RT_HD inline Instance placed_instance(const AffineD& to_world, int mesh, unsigned mask) {
  return {to_world.as_float(), inverse(to_world).as_float(), mesh, mask};
}

// The same, checked first (check_transform).
Instance make_instance(const AffineD& to_world, int mesh, unsigned mask,
                       const std::string& what);

// [listing:to_object_space]
// The ray in the instance's own space, the interval unchanged (the direction is not normalised,
// so t is the same on both rays). The origin is moved by the instance's translation first and
// then turned and scaled: o - T is exact where the origin lies near the instance (Sterbenz: a
// shadow ray leaving a small instance far from the world's origin), where to_object.point(o)
// would add two large numbers, L^-1 o and -L^-1 T, and keep only their rounding's difference.
RT_HD inline RayF to_object_space(const Instance& instance, const RayF& ray) {
  const Affine& w = instance.to_world;
  RayF local = ray;
  local.origin = instance.to_object.direction(
      {ray.origin.x - w.m[0][3], ray.origin.y - w.m[1][3], ray.origin.z - w.m[2][3]});
  local.direction = instance.to_object.direction(ray.direction);
  return local;
}
// [/listing:to_object_space]

// [listing:instance_hit]
// The closest (or any) hit of a two-level trace: the instance, the triangle's number in that
// instance's mesh, t along the world ray and the barycentrics. instance = -1 for a miss.
struct InstanceHit {
  float t = std::numeric_limits<float>::infinity();
  int instance = -1;
  int triangle = -1;
  float u = 0.0f, v = 0.0f;
};
// [/listing:instance_hit]

} // namespace rt::ch13
