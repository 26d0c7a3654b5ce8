// Chapter 13: a scene of instances. Meshes in their own space, each with its bottom-level tree
// (chapter 09's 4-wide packed tree, built once per mesh on the host); placements that put them
// in the world; the world boxes the top-level tree is built over; and, for tests and for
// measuring what instancing saves, the same scene flattened into one mesh.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bvh.h"
#include "camera_spec.h"
#include "instance.h"
#include "mesh_gen.h"
#include "wide_bvh.h"

namespace rt::ch13 {

using ch07::Aabb;

// One placement of a mesh, in double as it was made.
struct Placement {
  AffineD to_world;
  int mesh = 0;
  unsigned mask = 0xffffffffu;
};

struct InstanceScene {
  std::vector<ch04::Mesh> meshes;    // in their own space
  std::vector<Placement> placements; // instance k is placements[k]
  std::vector<Vec3f> albedo;         // one per instance: its colour in the shaded image
  std::optional<ch03::CameraSpec> camera;
  std::string description;
};

// The most instances a scene may have (ints number them, and a million of a small mesh is the
// chapter's largest scene): beyond it a scene is refused.
inline constexpr long long k_max_instances = 1LL << 24;

// Every placement checked (check_transform, naming the instance), the mesh numbers checked, and
// each made into an Instance. Throws InputError, one line, for the first one that fails.
std::vector<Instance> make_instances(const InstanceScene& scene);

// [listing:open_instances]
// Instances whose boxes overlap make a ray enter every one of them. An instance of a large mesh
// may therefore be opened (--open): instead of one top-level leaf with the mesh's whole box,
// it gets one leaf per subtree a few levels down the mesh's tree, each with that subtree's
// box, tighter once turned (Benthin et al. call this re-braiding). A node is opened only where
// all its children are subtrees (no triangles of its own), so the subtrees cover the mesh.
// Meshes of fewer than k_open_min_triangles triangles are not opened. Off by default: on an
// H200 every level opened made the dragon forest slower (the book's appendix C4), since each
// subtree entered moves the ray again and the top level over subtrees is deeper.
inline constexpr int k_open_min_triangles = 4096;
inline constexpr int k_max_open_levels = 3;
// [/listing:open_instances]

// The bottom level: each mesh's tree, its box in its own space, and the subtrees an instance
// of it is opened into (their root nodes and boxes; the root alone when it is not opened).
struct BottomLevel {
  std::vector<ch09::Wide4PackedBvh> trees;
  std::vector<Aabb> object_boxes;
  std::vector<std::vector<int>> open_nodes;
  std::vector<std::vector<Aabb>> open_boxes;
  double build_ms = 0.0; // all meshes, on the host
  double bytes = 0.0;    // the trees' nodes and triangle records
};
// `open_levels`: how many levels instances of large meshes are opened (0: never).
BottomLevel build_bottom_level(const std::vector<ch04::Mesh>& meshes, int open_levels = 0);

// [listing:world_box]
// An instance's box in the world: the eight corners of its mesh's box taken through the
// transform in double, and the box around them widened by a few ulps of its largest coordinate
// and rounded outward to float. The widening covers the rounding of the ray's own move to the
// instance's space (to_object_space, in float), so that a ray whose moved copy hits the mesh
// never misses its box on the way down.
RT_HD inline Aabb world_box(const Aabb& object, const AffineD& to_world) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3d p = to_world.point({corner & 1 ? object.hi.x : object.lo.x,
                                    corner & 2 ? object.hi.y : object.lo.y,
                                    corner & 4 ? object.hi.z : object.lo.z});
    const double v[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) {
      lo[a] = v[a] < lo[a] ? v[a] : lo[a];
      hi[a] = v[a] > hi[a] ? v[a] : hi[a];
    }
  }
  double largest = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double m = (lo[a] < 0 ? -lo[a] : lo[a]) > (hi[a] < 0 ? -hi[a] : hi[a])
                         ? (lo[a] < 0 ? -lo[a] : lo[a])
                         : (hi[a] < 0 ? -hi[a] : hi[a]);
    largest = m > largest ? m : largest;
  }
  const double pad = 16.0 * 0x1p-24 * largest; // 16 ulps of float at the largest coordinate
  constexpr double k_round = 1.0 + 0x1p-23;    // one float ulp of relative margin for rounding
  Aabb box;
  const auto down = [&](double x) {
    const double y = x - pad;
    return static_cast<float>(y < 0 ? y * k_round : y / k_round);
  };
  const auto up = [&](double x) {
    const double y = x + pad;
    return static_cast<float>(y < 0 ? y / k_round : y * k_round);
  };
  box.lo = {down(lo[0]), down(lo[1]), down(lo[2])};
  box.hi = {up(hi[0]), up(hi[1]), up(hi[2])};
  return box;
}
// [/listing:world_box]

// The scene as one mesh: each instance's triangles placed by its transform (in double,
// rounded once to float), concatenated in instance order; instance k's triangle t is triangle
// first_triangle[k] + t of the result. Throws InputError when the result would pass
// ch07::k_max_bvh_triangles (flattening does not fit where instancing does).
struct Flattened {
  ch04::Mesh mesh;
  std::vector<long long> first_triangle; // one per instance, and the total at the end
};
Flattened flatten(const InstanceScene& scene);

// [listing:spin]
// How the generated scenes place, and move, an instance: at `position`, turned by `yaw`
// radians about the vertical axis plus `speed` radians a second, scaled by `scale`. The moving
// scene's transforms are made from it every frame, on the device, in double.
struct Spin {
  Vec3d position;
  double yaw = 0.0, speed = 0.0, scale = 1.0;
};
RT_HD inline AffineD spin_transform(const Spin& s, double seconds) {
  const double angle = s.yaw + s.speed * seconds;
  double c = 0.0, sn = 0.0;
#if defined(__CUDA_ARCH__)
  sincos(angle, &sn, &c);
#else
  sn = std::sin(angle);
  c = std::cos(angle);
#endif
  AffineD a;
  a.m[0][0] = c * s.scale;
  a.m[0][2] = sn * s.scale;
  a.m[1][1] = s.scale;
  a.m[2][0] = -sn * s.scale;
  a.m[2][2] = c * s.scale;
  a.m[0][3] = s.position.x;
  a.m[1][3] = s.position.y;
  a.m[2][3] = s.position.z;
  return a;
}
// [/listing:spin]

// A generated forest: `count` copies of `tree` (mesh 0) on a square grid with a little jitter,
// each turned, scaled by 0.8-1.2 and coloured at random from `seed`, standing on a ground of
// two triangles (mesh 1, one instance, last). The spins are the trees'; `speed` turns each
// (0: a still forest). The camera looks over the grid from above one corner.
struct Forest {
  InstanceScene scene;
  std::vector<Spin> spins; // one per tree, instances 0 .. count-1
};
Forest make_forest(const ch04::Mesh& tree, int count, unsigned seed, double speed = 0.0);

} // namespace rt::ch13
