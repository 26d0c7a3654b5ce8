// Chapter 13: building and checking instance transforms. See instance.h.
#include "instance.h"

#include <cmath>
#include <sstream>

#include "rt/error.h"
#include "supported_range.h"

namespace rt::ch13 {

AffineD translation(Vec3d t) {
  AffineD a;
  a.m[0][3] = t.x;
  a.m[1][3] = t.y;
  a.m[2][3] = t.z;
  return a;
}

AffineD scaling(Vec3d s) {
  AffineD a;
  a.m[0][0] = s.x;
  a.m[1][1] = s.y;
  a.m[2][2] = s.z;
  return a;
}

// Rodrigues' formula: R = cos I + sin [k]x + (1 - cos) k k^T for the unit axis k.
AffineD rotation(Vec3d axis, double radians) {
  const double length = std::sqrt(dot(axis, axis));
  if (!(length > 0.0) || !std::isfinite(length) || !std::isfinite(radians))
    throw InputError("a rotation needs a finite, non-zero axis and a finite angle");
  const Vec3d k = axis / length;
  const double c = std::cos(radians), s = std::sin(radians), v = 1.0 - c;
  AffineD a;
  a.m[0][0] = c + k.x * k.x * v;
  a.m[0][1] = k.x * k.y * v - k.z * s;
  a.m[0][2] = k.x * k.z * v + k.y * s;
  a.m[1][0] = k.y * k.x * v + k.z * s;
  a.m[1][1] = c + k.y * k.y * v;
  a.m[1][2] = k.y * k.z * v - k.x * s;
  a.m[2][0] = k.z * k.x * v - k.y * s;
  a.m[2][1] = k.z * k.y * v + k.x * s;
  a.m[2][2] = c + k.z * k.z * v;
  return a;
}

void check_transform(const AffineD& a, const std::string& what) {
  const auto fail = [&](const std::string& problem) {
    throw InputError(what + ": " + problem);
  };
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(a.m[r][c]))
        fail("its transform has a value that is not finite (row " + std::to_string(r) +
             ", column " + std::to_string(c) + ")");
  double product = 1.0;
  for (int c = 0; c < 3; ++c) {
    const double length =
        std::sqrt(a.m[0][c] * a.m[0][c] + a.m[1][c] * a.m[1][c] + a.m[2][c] * a.m[2][c]);
    if (!(length >= k_min_scale && length <= k_max_scale)) {
      std::ostringstream out;
      out << "its transform scales axis "
          << "xyz"[c] << " by " << length << ", outside the supported " << k_min_scale << " to "
          << k_max_scale;
      fail(out.str());
    }
    product *= length;
  }
  const double det = determinant(a);
  if (!(std::abs(det) >= k_min_volume_ratio * product)) {
    std::ostringstream out;
    out << "its transform is singular or nearly so (determinant " << det << " for axes scaled "
        << "by a product of " << product << ")";
    fail(out.str());
  }
  for (int r = 0; r < 3; ++r)
    if (!(std::abs(a.m[r][3]) <= ch03::k_max_coordinate)) {
      std::ostringstream out;
      out << "its translation " << a.m[r][3] << " lies beyond the supported range (+-"
          << ch03::k_max_coordinate << ")";
      fail(out.str());
    }
}

Instance make_instance(const AffineD& to_world, int mesh, unsigned mask,
                       const std::string& what) {
  check_transform(to_world, what);
  return placed_instance(to_world, mesh, mask);
}

} // namespace rt::ch13
