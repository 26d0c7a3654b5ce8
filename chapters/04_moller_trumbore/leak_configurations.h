// Chapter 04: the leak configurations the program reports and the tests check: closed meshes
// at the origin and translated by 1e5, where a float ulp is 0.008 and rounding is roughest.
#pragma once

#include "mesh_gen.h"
#include "triangles.h"

namespace rt::ch04 {

struct LeakConfiguration {
  const char* name;
  bool icosphere; // else a box
  Vec3d offset;   // where the mesh's centre is
  float spread;   // ray origins lie within this distance of the centre
  unsigned seed;

  Mesh make_mesh() const {
    const Vec3d half_size{1, 1, 1};
    return icosphere ? make_icosphere(1, offset, 1.0)
                     : make_box(offset - half_size, offset + half_size, 3);
  }
  Vec3f inside() const { return offset.as<float>(); }
};

inline constexpr LeakConfiguration k_leak_configurations[] = {
    {"icosphere (80) at 0", true, {0, 0, 0}, 0.3f, 101},
    {"icosphere (80) at 1e5", true, {1e5, 1e5, 1e5}, 0.3f, 102},
    {"box (108) at 0", false, {0, 0, 0}, 0.3f, 103},
    {"box (108) at 1e5", false, {1e5, -1e5, 1e5}, 0.3f, 104}};

// Both intersection tests, for suites that run every check on each.
inline constexpr TriangleVariant k_variants[] = {TriangleVariant::moller_trumbore,
                                                 TriangleVariant::watertight};

} // namespace rt::ch04
