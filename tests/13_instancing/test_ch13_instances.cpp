// Chapter 13 tests: transforms and their checks, world boxes, and the two-level walk against
// the same scene flattened into one mesh (brute force over every triangle); masks; leaks
// through placed and split closed meshes; the moving scene against one built at the same
// time; the generated forest.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "rt_catch.h"

#include "adversarial_rays.h"
#include "instance.h"
#include "instance_cases.h"
#include "instance_scene.h"
#include "instanced_paths.h"
#include "instancing_program.h"
#include "mesh_gen.h"
#include "ray_io.h"
#include "rt/error.h"
#include "run_program.h"
#include "supported_range.h"
#include "trace.h"
#include "triangles.h"
#include "two_level_scene.h"
#include "wide_traverse.h"

using namespace rt;
using namespace rt::ch13;
using namespace rt::ch13::testing;
using rt::testing::contains;
namespace fs = std::filesystem;

namespace {

// The message of the InputError `run` throws, or "" when it throws none.
template <class F> std::string input_error_of(F&& run) {
  try {
    run();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// One line, naming `what`, saying `says`.
void check_refusal(const std::string& message, const std::string& what,
                   const std::string& says) {
  CAPTURE(message);
  CHECK_THAT(message, contains(what + ": "));
  CHECK_THAT(message, contains(says));
  CHECK(message.find('\n') == std::string::npos);
}

ch07::Aabb box_of(const ch04::Mesh& mesh) {
  ch07::Aabb box;
  for (const Vec3f& v : mesh.vertices) box.grow(v);
  return box;
}

bool box_contains(const ch07::Aabb& box, Vec3f p) {
  return box.lo.x <= p.x && p.x <= box.hi.x && box.lo.y <= p.y && p.y <= box.hi.y &&
         box.lo.z <= p.z && p.z <= box.hi.z;
}

// The scene on the CPU backend: its bottom level built here.
struct CpuScene {
  BottomLevel bottom;
  TwoLevelScene scene;
  CpuScene(const InstanceScene& s, std::vector<Spin> spins = {})
      : bottom(build_bottom_level(s.meshes)), scene(Backend::cpu, s, bottom, std::move(spins)) {
  }
};

std::vector<InstanceHit> trace_all(const TwoLevelScene& scene, Query query,
                                   const std::vector<RayF>& rays) {
  std::vector<InstanceHit> hits(rays.size());
  trace_rays(scene, query, rays.data(), static_cast<int>(rays.size()), hits.data());
  return hits;
}

// Chapter 04's closest hit over every triangle of the flattened mesh, the watertight test.
std::vector<ch04::MeshHit> brute_force(const ch04::Mesh& mesh, const std::vector<RayF>& rays) {
  return ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, rays);
}

long long flat_id(const Flattened& flat, const InstanceHit& hit) {
  return hit.instance < 0 ? -1 : flat.first_triangle[hit.instance] + hit.triangle;
}

// The barycentric distance of a hit from its triangle's nearest edge.
float distance_to_edge(float u, float v) { return std::min({u, v, 1.0f - u - v}); }

} // namespace

// ---------------------------------------------------------------------------------------------
// Transforms

TEST_CASE("an instance's two transforms undo each other", "[ch13][transform]") {
  const AffineD a = translation({3.0, -2.0, 1e4}) * rotation({1.0, 2.0, 3.0}, 0.7) *
                    scaling({2.0, 0.5, 1e-2});
  const AffineD identity = inverse(a) * a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) CHECK(std::abs(identity.m[r][c] - (r == c ? 1.0 : 0.0)) < 1e-9);
}

TEST_CASE("inverse(a) * a is the identity for random transforms over the whole range",
          "[ch13][transform]") {
  // The linear part is held to 1e-9 absolutely. The translation column of inverse(a) * a is
  // inverse(a)'s rows applied to a's translation, minus the same sum rounded once: its error
  // is a few double ulps of |row| * |translation|, up to 1e3 * 1e5 = 1e8 for a scale of 1e-3
  // at a translation of 1e5 (1e-8 absolute), so it is held to 1e-9 relative to that product:
  // still a million times below what one float rounding of the transform costs.
  std::mt19937 random(1301);
  double worst_linear = 0.0, worst_translation = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const AffineD a = random_transform(random, k_min_scale, k_max_scale, 1e5);
    REQUIRE_NOTHROW(check_transform(a, "random transform"));
    const AffineD inv = inverse(a);
    const AffineD identity = inv * a;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        worst_linear =
            std::max(worst_linear, std::abs(identity.m[r][c] - (r == c ? 1.0 : 0.0)));
      const double size = std::abs(inv.m[r][0] * a.m[0][3]) +
                          std::abs(inv.m[r][1] * a.m[1][3]) + std::abs(inv.m[r][2] * a.m[2][3]);
      worst_translation =
          std::max(worst_translation, std::abs(identity.m[r][3]) / std::max(1.0, size));
    }
    // And the other way round: a * inverse(a), the map the world box is built with.
    const AffineD back = a * inv;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        worst_linear = std::max(worst_linear, std::abs(back.m[r][c] - (r == c ? 1.0 : 0.0)));
  }
  CAPTURE(worst_linear, worst_translation);
  CHECK(worst_linear < 1e-9);
  CHECK(worst_translation < 1e-9);
}

TEST_CASE("check_transform refuses what is out of range, in one line naming the instance",
          "[ch13][transform]") {
  const std::string what = "instance 7";
  const auto refusal = [&](const AffineD& a) {
    return input_error_of([&] { check_transform(a, what); });
  };
  for (const double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity()})
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        AffineD a = rotation({1.0, 1.0, 0.0}, 0.3);
        a.m[r][c] = bad;
        CAPTURE(r, c, bad);
        check_refusal(refusal(a), what, "not finite");
      }
  for (int axis = 0; axis < 3; ++axis) {
    CAPTURE(axis);
    Vec3d small{1.0, 1.0, 1.0}, large{1.0, 1.0, 1.0};
    const double below = std::nextafter(k_min_scale, 0.0),
                 above = std::nextafter(k_max_scale, 1e9);
    (axis == 0 ? small.x : axis == 1 ? small.y : small.z) = below;
    (axis == 0 ? large.x : axis == 1 ? large.y : large.z) = above;
    check_refusal(refusal(scaling(small)), what, std::string("scales axis ") + "xyz"[axis]);
    check_refusal(refusal(scaling(large)), what, std::string("scales axis ") + "xyz"[axis]);
    // A zero column: the axis is flattened away.
    AffineD zero;
    for (int r = 0; r < 3; ++r) zero.m[r][axis] = 0.0;
    check_refusal(refusal(zero), what, std::string("scales axis ") + "xyz"[axis]);
    // Translation just beyond the supported coordinates, either way.
    for (const double sign : {1.0, -1.0}) {
      AffineD far;
      far.m[axis][3] = sign * std::nextafter(ch03::k_max_coordinate, 1e300);
      check_refusal(refusal(far), what, "beyond the supported range");
    }
  }
  // Two equal columns: every length in range, the determinant zero.
  AffineD twins = rotation({0.2, 0.9, 0.4}, 1.1) * scaling({2.0, 3.0, 0.5});
  for (int r = 0; r < 3; ++r) twins.m[r][2] = twins.m[r][0];
  check_refusal(refusal(twins), what, "singular");
  // Nearly equal columns: the volume below k_min_volume_ratio of the lengths' product.
  AffineD nearly;
  nearly.m[0][1] = 1.0;
  nearly.m[1][1] = 1e-7;
  check_refusal(refusal(nearly), what, "singular");

  // The boundary values themselves are accepted: sqrt(x * x) == |x| in binary floating point,
  // so an axis scaled by exactly k_min_scale or k_max_scale measures exactly that.
  CHECK_NOTHROW(check_transform(scaling({k_min_scale, k_max_scale, 1.0}), what));
  CHECK_NOTHROW(check_transform(scaling({-k_max_scale, 1.0, -k_min_scale}), what));
  CHECK_NOTHROW(check_transform(
      translation({ch03::k_max_coordinate, -ch03::k_max_coordinate, ch03::k_max_coordinate}),
      what));
  AffineD just_enough; // volume ratio exactly at the limit
  just_enough.m[0][1] = std::sqrt(1.0 - k_min_volume_ratio * k_min_volume_ratio);
  just_enough.m[1][1] = k_min_volume_ratio;
  CAPTURE(determinant(just_enough));
  CHECK_NOTHROW(check_transform(scaling({1.0, 1.0, 2.0}) * just_enough, what));
  // make_instance checks first, placed_instance does not.
  check_refusal(input_error_of([&] { make_instance(twins, 0, 1u, what); }), what, "singular");
}

TEST_CASE("make_instances refuses a mesh that does not exist, naming the instance",
          "[ch13][transform]") {
  InstanceScene scene;
  scene.meshes.push_back(ch04::make_icosphere(0, {0, 0, 0}, 1.0));
  scene.meshes.push_back(ch04::make_box({0, 0, 0}, {1, 1, 1}, 1));
  for (int k = 0; k < 4; ++k) scene.placements.push_back({translation({3.0 * k, 0, 0}), k % 2});
  REQUIRE(make_instances(scene).size() == 4);
  for (const int bad : {-1, 2, 1000}) {
    InstanceScene broken = scene;
    broken.placements[2].mesh = bad;
    check_refusal(input_error_of([&] { make_instances(broken); }), "instance 2",
                  "mesh " + std::to_string(bad) + " does not exist (2 meshes)");
  }
  // The first bad transform is named, by its place in the list.
  InstanceScene broken = scene;
  broken.placements[3].to_world.m[1][1] = 0.0;
  check_refusal(input_error_of([&] { make_instances(broken); }), "instance 3", "scales axis y");
  // More than k_max_instances placements (16.8 million) would take 1.7 GB to build here; the
  // forest, which refuses its count before it places anything, checks the same bound.
  for (const long long count : {0LL, -3LL, k_max_instances})
    CHECK_THAT(
        input_error_of([&] { make_forest(scene.meshes[0], static_cast<int>(count), 1); }),
        contains("a forest of " + std::to_string(count) + " trees"));
}

// ---------------------------------------------------------------------------------------------
// World boxes

TEST_CASE("an instance's world box holds every vertex of its mesh as placed",
          "[ch13][world-box]") {
  // The vertices placed in double and rounded to float are what the flattened scene holds, and
  // (up to the ray's own rounding, which the widening covers) what the ray moved to the
  // instance's space sees. The box must hold them all, and be no looser than its widening.
  const std::vector<ch04::Mesh> meshes = {ch04::make_icosphere(3, {0.3, -0.2, 0.1}, 1.0),
                                          ch04::make_box({-1, -2, -0.5}, {2, 1, 0.5}, 4),
                                          ch04::make_icosphere(1, {1e3, 0.0, -2e3}, 7.0)};
  std::mt19937 random(1302);
  std::vector<AffineD> transforms;
  for (int k = 0; k < 300; ++k)
    transforms.push_back(random_transform(random, k_min_scale, k_max_scale, 1e5));
  // The stiff corner: a thousandth of the size, 1e5 away.
  transforms.push_back(translation({1e5, -1e5, 1e5}) * scaling({1e-3, 1e-3, 1e-3}));
  transforms.push_back(translation({-1e5, 1e5, 3.0}) * rotation({1, 1, 1}, 2.0) *
                       scaling({1e-3, 1e3, 1e-3}));
  long long vertices = 0;
  for (const ch04::Mesh& mesh : meshes) {
    const ch07::Aabb object = box_of(mesh);
    for (const AffineD& a : transforms) {
      const ch07::Aabb box = world_box(object, a);
      // The exact box of the placed vertices (float-rounded), to bound the looseness.
      ch07::Aabb tight;
      bool all_inside = true;
      for (const Vec3f& v : mesh.vertices) {
        const Vec3f p = a.point(v.as<double>()).as<float>();
        tight.grow(p);
        all_inside = all_inside && box_contains(box, p);
        ++vertices;
      }
      CAPTURE(box.lo.x, box.lo.y, box.lo.z, box.hi.x, box.hi.y, box.hi.z);
      REQUIRE(all_inside);
      // No looser than the eight corners' box (which may exceed the vertices' under rotation)
      // plus the widening: 16 float ulps of the largest coordinate and a little rounding.
      double largest = 0.0, corners_extent = 0.0;
      for (int axis = 0; axis < 3; ++axis) {
        largest =
            std::max({largest, std::abs(double(box.lo[axis])), std::abs(double(box.hi[axis]))});
        corners_extent = std::max(corners_extent, double(box.hi[axis]) - box.lo[axis]);
      }
      const Vec3d size = (object.hi - object.lo).as<double>();
      double reach = 0.0; // how far a corner's box can stick out past the vertices' box
      for (int c = 0; c < 3; ++c)
        reach +=
            std::sqrt(a.m[0][c] * a.m[0][c] + a.m[1][c] * a.m[1][c] + a.m[2][c] * a.m[2][c]) *
            size[c];
      for (int axis = 0; axis < 3; ++axis) {
        CHECK(tight.lo[axis] - box.lo[axis] <= reach + 20.0 * 0x1p-24 * largest);
        CHECK(box.hi[axis] - tight.hi[axis] <= reach + 20.0 * 0x1p-24 * largest);
      }
    }
  }
  CHECK(vertices > 100000);
}

TEST_CASE("a ray whose copy in the instance's space hits the mesh enters the world box",
          "[ch13][world-box]") {
  // world_box's widening is there for this: the top level must never cull a hit that the
  // ray, moved to the instance's space in float, would find (a box of the eight corners rounded
  // to nearest, not widened, misses about 3% of these hits). The hardest rays graze the box:
  // a cube's faces lie on its box, so rays at the cube's edges, from near and from 1e3 and 1e5
  // times its size away, where the ray's move rounds most.
  std::mt19937 random(1316);
  const std::vector<ch04::Mesh> meshes = {ch04::make_box({-1, -1, -1}, {1, 1, 1}, 2),
                                          ch04::make_icosphere(2, {0, 0, 0}, 1.0)};
  long long object_hits = 0, culled = 0;
  for (int c = 0; c < 48; ++c) {
    InstanceScene scene;
    scene.meshes = {meshes[c % 2]};
    // Axis-aligned (a quarter turn keeps the faces on the box) or turned at random.
    const Vec3d s{log_uniform(random, 1e-2, 1e2), log_uniform(random, 1e-2, 1e2),
                  log_uniform(random, 1e-2, 1e2)};
    const AffineD turn =
        c % 3 == 0 ? rotation(random_unit_vector(random), 2.0) : rotation({0, 0, 1}, 0.0);
    const AffineD a =
        translation({c % 4 < 2 ? 0.5 : 1e4, -0.25, c % 4 < 2 ? 3.0 : -3e4}) * turn * scaling(s);
    scene.placements = {{a, 0}};
    const CpuScene cpu(scene);
    const TwoLevelView view = cpu.scene.view();
    const ch04::Mesh placed = flatten(scene).mesh;
    const double size = std::max({s.x, s.y, s.z});
    const double distance = c % 8 < 4 ? 3.0 : (c % 8 < 6 ? 1e3 : 1e5);
    const Vec3d centre = a.point({0, 0, 0});
    std::uniform_int_distribution<int> pick(0, int(placed.triangles.size()) - 1);
    std::uniform_real_distribution<float> along(0.0f, 1.0f);
    for (int i = 0; i < 4000; ++i) {
      const ch04::IndexedTriangle t = placed.triangles[pick(random)];
      const Vec3f p = placed.vertices[t.v0], q = placed.vertices[t.v1];
      const Vec3f target = p + (q - p) * along(random);
      const Vec3f origin =
          (centre + random_unit_vector(random) * (distance * size)).as<float>();
      const RayF ray{origin, target - origin};
      const ch07::TraceHit object = ch09::trace_wide<Query::closest>(
          view.meshes[0], to_object_space(view.instances[0], ray));
      if (object.triangle < 0) continue;
      ++object_hits;
      const InstanceHit two = trace_instances<Query::closest>(view, ray);
      culled += two.instance < 0 || !same_bits(two.t, object.t);
    }
  }
  CAPTURE(object_hits, culled);
  CHECK(object_hits > 100000);
  CHECK(culled == 0);
}

// ---------------------------------------------------------------------------------------------
// Two levels against one

namespace {

// Meshes at distinct places in their own space, each placed once by the identity.
InstanceScene identity_scene() {
  InstanceScene scene;
  scene.meshes = {ch04::make_icosphere(3, {0.0, 0.0, 0.0}, 1.0),
                  ch04::make_box({2.0, -1.0, -1.0}, {3.5, 0.5, 1.0}, 5),
                  ch04::make_icosphere(2, {-2.5, 0.5, 0.5}, 0.8),
                  ch04::make_box({-1.0, 1.5, -2.0}, {1.0, 2.0, 2.0}, 3),
                  ch04::make_icosphere(4, {0.5, -2.0, 1.5}, 0.6)};
  for (int m = 0; m < int(scene.meshes.size()); ++m) scene.placements.push_back({AffineD{}, m});
  return scene;
}

} // namespace

TEST_CASE("identity placements: two levels give the flattened scene's hits bit for bit",
          "[ch13][two-level]") {
  const InstanceScene scene = identity_scene();
  const CpuScene cpu(scene);
  const Flattened flat = flatten(scene);
  // Placed by the identity in double, rounded to float: the very vertices of the meshes.
  for (std::size_t m = 0, base = 0; m < scene.meshes.size(); ++m) {
    for (std::size_t v = 0; v < scene.meshes[m].vertices.size(); ++v)
      REQUIRE(same_bits(flat.mesh.vertices[base + v], scene.meshes[m].vertices[v]));
    base += scene.meshes[m].vertices.size();
  }
  const std::vector<RayF> rays = rays_into_box(scene_box(scene), 0.6, 4000, 1303);
  const std::vector<ch04::MeshHit> reference = brute_force(flat.mesh, rays);
  const std::vector<InstanceHit> closest = trace_all(cpu.scene, Query::closest, rays);
  const std::vector<InstanceHit> any = trace_all(cpu.scene, Query::any, rays);
  long long hits = 0, ties = 0, wrong = 0, any_wrong = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const long long id = flat_id(flat, closest[i]);
    const bool same_t = same_bits(closest[i].t, reference[i].t);
    hits += reference[i].triangle >= 0;
    if (id == reference[i].triangle && same_t) {
      // The barycentrics are those of the same test on the same triangle.
      if (id >= 0) {
        const ch04::TriangleHitF h =
            ch04::intersect_watertight(rays[i], flat.mesh.triangle(int(id)));
        if (!h.hit || !same_bits(h.u, closest[i].u) || !same_bits(h.v, closest[i].v)) ++wrong;
      }
    } else if (id >= 0 && reference[i].triangle >= 0 && same_t) {
      ++ties; // another triangle at exactly the same t: the order of testing decides
    } else {
      ++wrong;
      UNSCOPED_INFO("ray " << i << ": two levels " << id << " t " << closest[i].t
                           << ", flattened " << reference[i].triangle << " t "
                           << reference[i].t);
    }
    // Any hit: hit or not as the closest, and a real hit of the triangle it names.
    const long long any_id = flat_id(flat, any[i]);
    if ((any_id >= 0) != (reference[i].triangle >= 0)) {
      ++any_wrong;
    } else if (any_id >= 0) {
      const ch04::TriangleHitF h =
          ch04::intersect_watertight(rays[i], flat.mesh.triangle(int(any_id)));
      if (!h.hit || !same_bits(h.t, any[i].t) || !(any[i].t >= reference[i].t)) ++any_wrong;
    }
  }
  CAPTURE(hits, ties, wrong, any_wrong);
  REQUIRE(hits > 1000); // the rays really meet the scene
  CHECK(wrong == 0);
  CHECK(any_wrong == 0);
  CHECK(ties < 10);
}

TEST_CASE("general transforms: two levels against the flattened scene", "[ch13][two-level]") {
  // Rotation, non-uniform scale and translation, several instances of each mesh (one
  // bottom-level tree each). The two traces see different floats: the flattened vertices
  // rounded once in the world, the ray rounded once into the instance's space. Where they
  // differ it is at an edge (a ray through the seam between triangles, or past a silhouette)
  // or between two surfaces at the same distance.
  InstanceScene scene;
  // The third mesh, of 5 120 triangles, is large enough for its instances to be opened into
  // subtrees at the top level (instance_scene.h).
  scene.meshes = {ch04::make_icosphere(2, {0.0, 0.0, 0.0}, 1.0),
                  ch04::make_box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}, 3),
                  ch04::make_icosphere(4, {0.2, 0.0, -0.1}, 1.3)};
  std::mt19937 random(1304);
  for (int k = 0; k < 15; ++k)
    scene.placements.push_back(
        {random_transform(random, 0.3, 3.0, 6.0), k % 7 == 3 ? 2 : k % 2});
  const CpuScene cpu(scene);
  REQUIRE(cpu.bottom.trees.size() == 3);
  const Flattened flat = flatten(scene);
  // Half the rays aimed at the scene's box, half at random points of its triangles.
  std::vector<RayF> rays = rays_into_box(scene_box(scene), 0.3, 6000, 1305);
  {
    std::mt19937 random_aim(1314);
    const std::vector<RayF> from = rays_into_box(scene_box(scene), 0.3, 6000, 1315);
    std::uniform_int_distribution<int> pick(0, int(flat.mesh.triangles.size()) - 1);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (const RayF& ray : from) {
      const ch04::TriangleF t = flat.mesh.triangle(pick(random_aim));
      float u = unit(random_aim), v = unit(random_aim);
      if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
      const Vec3f target = t.v0 * (1.0f - u - v) + t.v1 * u + t.v2 * v;
      if (target != ray.origin) rays.push_back({ray.origin, target - ray.origin});
    }
  }
  const std::vector<ch04::MeshHit> reference = brute_force(flat.mesh, rays);
  const std::vector<InstanceHit> closest = trace_all(cpu.scene, Query::closest, rays);
  long long hits = 0, same = 0, near_t = 0, at_edge = 0, unexplained = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    hits += reference[i].triangle >= 0;
    const long long id = flat_id(flat, closest[i]);
    if (id == reference[i].triangle) {
      ++same;
      continue;
    }
    if (id >= 0 && reference[i].triangle >= 0 &&
        std::abs(closest[i].t - reference[i].t) <= 1e-4f * reference[i].t) {
      ++near_t;
      continue;
    }
    // Otherwise the flattened hit (or, where the flattened ray missed, the instanced one) must
    // lie within 1e-3 of an edge of its triangle.
    float edge = 1.0f;
    if (reference[i].triangle >= 0) {
      const ch04::TriangleHitF h =
          ch04::intersect_watertight(rays[i], flat.mesh.triangle(reference[i].triangle));
      edge = h.hit ? distance_to_edge(h.u, h.v) : 1.0f;
    } else {
      edge = distance_to_edge(closest[i].u, closest[i].v);
    }
    if (edge <= 1e-3f) {
      ++at_edge;
    } else {
      ++unexplained;
      UNSCOPED_INFO("ray " << i << ": two levels " << id << " t " << closest[i].t
                           << ", flattened " << reference[i].triangle << " t " << reference[i].t
                           << ", " << edge << " from an edge");
    }
  }
  CAPTURE(hits, same, near_t, at_edge, unexplained);
  REQUIRE(hits > 7000);
  CHECK(same >= 0.999 * double(rays.size()));
  CHECK(unexplained == 0);
}

TEST_CASE("masks: a ray tests only the instances whose mask shares a bit with its own",
          "[ch13][mask]") {
  // Two spheres on the x axis, the nearer masked 0x2, the farther 0x1; a third, off the axis,
  // masked 0x3, stands beside them.
  InstanceScene scene;
  scene.meshes = {ch04::make_icosphere(2, {0.0, 0.0, 0.0}, 1.0)};
  scene.placements = {{translation({3.0, 0.0, 0.0}), 0, 0x2u},
                      {translation({6.0, 0.0, 0.0}) * scaling({1.5, 1.0, 0.5}), 0, 0x1u},
                      {translation({4.5, 4.0, 0.0}), 0, 0x3u}};
  const CpuScene cpu(scene);
  const TwoLevelView view = cpu.scene.view();
  const RayF along_x{{-5.0f, 0.01f, 0.02f}, {1.0f, 0.0f, 0.0f}};
  CHECK(trace_instances<Query::closest>(view, along_x).instance == 0);
  CHECK(trace_instances<Query::closest>(view, along_x, 0x2u).instance == 0);
  CHECK(trace_instances<Query::closest>(view, along_x, 0x1u).instance == 1);
  CHECK(trace_instances<Query::closest>(view, along_x, 0x3u).instance == 0);
  CHECK(trace_instances<Query::closest>(view, along_x, 0x4u).instance == -1);
  CHECK(trace_instances<Query::any>(view, along_x, 0x1u).instance == 1);
  CHECK(trace_instances<Query::any>(view, along_x, 0x4u).instance == -1);
  // The walk counts the instances it enters: a masked-out one is not moved into.
  TwoLevelCounters counters;
  trace_instances<Query::closest>(view, along_x, 0x1u, counters);
  CHECK(counters.instances == 1);

  // Random rays: with mask 0x1, the scene is the one without the instances masked 0x2 only.
  InstanceScene without = scene;
  without.placements.erase(without.placements.begin());
  const CpuScene cpu_without(without);
  const std::vector<RayF> rays = rays_into_box(scene_box(scene), 0.5, 3000, 1306);
  long long hit_masked = 0;
  for (const RayF& ray : rays) {
    const InstanceHit masked = trace_instances<Query::closest>(view, ray, 0x1u);
    const InstanceHit reference =
        trace_instances<Query::closest>(cpu_without.scene.view(), ray);
    REQUIRE(masked.instance != 0);
    REQUIRE(masked.instance == (reference.instance < 0 ? -1 : reference.instance + 1));
    REQUIRE(same_bits(masked.t, reference.t));
    REQUIRE(masked.triangle == reference.triangle);
    hit_masked += masked.instance >= 0;
  }
  CHECK(hit_masked > 300);
}

// ---------------------------------------------------------------------------------------------
// Watertightness across the transform

namespace {

// Rays fired from inside a closed mesh placed by `to_world` (origins within `spread` of
// `inside`, in the world), at its placed vertices and at points of its placed edges: the
// placed mesh is the flattened one, each vertex placed in double and rounded to float.
struct LeakCase {
  std::string name;
  AffineD to_world;
  double object_radius;
};

long long count_misses(const TwoLevelScene& scene, const std::vector<RayF>& rays) {
  long long misses = 0;
  for (const InstanceHit& hit : trace_all(scene, Query::closest, rays))
    misses += hit.instance < 0;
  return misses;
}

// The sphere's triangles above and below the plane y = centre (by their centroids): two open
// meshes with the same vertex array, so the edges of the cut are made of the same floats in
// both.
std::pair<ch04::Mesh, ch04::Mesh> split_at_equator(const ch04::Mesh& sphere, float centre_y) {
  ch04::Mesh top, bottom;
  top.vertices = bottom.vertices = sphere.vertices;
  for (const ch04::IndexedTriangle& t : sphere.triangles) {
    const float y = sphere.vertices[t.v0].y + sphere.vertices[t.v1].y + sphere.vertices[t.v2].y;
    (y > 3.0f * centre_y ? top : bottom).triangles.push_back(t);
  }
  return {top, bottom};
}

// The edges one triangle of `a` and one of `b` share (as vertex index pairs).
std::vector<std::pair<int, int>> shared_edges(const ch04::Mesh& a, const ch04::Mesh& b) {
  const auto edges = [](const ch04::Mesh& m) {
    std::set<std::pair<int, int>> out;
    for (const ch04::IndexedTriangle& t : m.triangles)
      for (const auto& [p, q] : {std::pair{t.v0, t.v1}, {t.v1, t.v2}, {t.v2, t.v0}})
        out.insert({std::min(p, q), std::max(p, q)});
    return out;
  };
  const auto ea = edges(a), eb = edges(b);
  std::vector<std::pair<int, int>> out;
  std::set_intersection(ea.begin(), ea.end(), eb.begin(), eb.end(), std::back_inserter(out));
  return out;
}

// Rays from within `spread` of `inside` at the placed ends and random points of the edges.
std::vector<RayF> rays_at_edges(const ch04::Mesh& object, const AffineD& to_world,
                                const std::vector<std::pair<int, int>>& edges, Vec3f inside,
                                float spread, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), along(0.0f, 1.0f);
  std::uniform_int_distribution<int> pick(0, int(edges.size()) - 1), kind(0, 2);
  std::vector<RayF> rays;
  while (static_cast<int>(rays.size()) < count) {
    const Vec3f jitter{unit(random), unit(random), unit(random)};
    if (!(length_squared(jitter) <= 1.0f)) continue;
    const Vec3f origin = inside + jitter * spread;
    const auto [p, q] = edges[pick(random)];
    const Vec3f a = to_world.point(object.vertices[p].as<double>()).as<float>();
    const Vec3f b = to_world.point(object.vertices[q].as<double>()).as<float>();
    const int k = kind(random);
    const Vec3f target = k == 0 ? a : a + (b - a) * along(random);
    if (target == origin) continue;
    rays.push_back({origin, target - origin});
  }
  return rays;
}

std::vector<LeakCase> leak_cases() {
  // The placed sphere's radius is kept at least a thousandth of its distance from the origin
  // (and at least 1), so that float can place a ray inside it at all: a sphere of 1e-3 at 1e5,
  // where float's spacing is 8e-3, has no inside a float ray could start from. The object's
  // radius follows from the scale.
  std::vector<LeakCase> cases;
  const auto add = [&](std::string name, Vec3d t, Vec3d axis, double angle, Vec3d s) {
    const double reach = std::sqrt(dot(t, t));
    const double placed_radius = std::max(1.0, 1e-3 * reach);
    const double smallest = std::min({s.x, s.y, s.z});
    cases.push_back({std::move(name), translation(t) * rotation(axis, angle) * scaling(s),
                     placed_radius / smallest});
  };
  add("identity", {0, 0, 0}, {0, 1, 0}, 0.0, {1, 1, 1});
  add("rotated", {0, 0, 0}, {1, 2, 3}, 0.9, {1, 1, 1});
  add("scale 1e-3", {2.0, -1.0, 0.5}, {0, 0, 1}, 0.4, {1e-3, 1e-3, 1e-3});
  add("scale 1e3", {-3.0, 0.0, 1.0}, {1, 0, 0}, 2.2, {0.999e3, 0.999e3, 0.999e3});
  // A rotation's columns are unit only to rounding: the extremes are kept a hair inside.
  add("non-uniform 1e-3..1e3", {10.0, 20.0, -5.0}, {1, -1, 2}, 1.3, {1.001e-3, 1.0, 0.999e3});
  add("1e4 away", {1e4, -7e3, 3e3}, {0.3, 1, 0}, -0.7, {2.0, 0.5, 1.0});
  add("1e5 away, scale 1e-3", {1e5, 1e5, -1e5}, {2, 1, 1}, 0.6, {1e-3, 1e-3, 1e-3});
  add("1e5 away, scale 1e3", {-1e5, 3e4, 1e5}, {1, 1, 1}, 2.9, {0.999e3, 5e2, 0.999e3});
  add("1e5 away, non-uniform", {-6e4, -1e5, 2e4}, {0, 1, 1}, -2.0, {1e-2, 3.0, 1e2});
  return cases;
}

} // namespace

TEST_CASE("a closed mesh stays closed when placed: no leaks under any transform in range",
          "[ch13][watertight]") {
  // Why there can be none. The ray's origin lies deep inside the placed sphere; moved into the
  // instance's space (in float), it is off by a few float ulps of its coordinates there, far
  // less than the distance to the surface, so it is still inside the object's closed mesh.
  // Chapter 04's watertight test lets no ray out of a closed mesh whose triangles share their
  // vertices' floats, whatever the ray; the origin is inside the instance's world box, so the
  // top level enters it. So every ray hits, whatever float does to the placed vertices.
  for (const LeakCase& c : leak_cases()) {
    CAPTURE(c.name);
    InstanceScene scene;
    scene.meshes = {ch04::make_icosphere(3, {0.0, 0.0, 0.0}, c.object_radius)};
    scene.placements = {{c.to_world, 0}};
    const CpuScene cpu(scene);
    const ch04::Mesh placed = flatten(scene).mesh;
    const Vec3f centre = c.to_world.point({0.0, 0.0, 0.0}).as<float>();
    double smallest_scale = 1e300;
    for (int col = 0; col < 3; ++col)
      smallest_scale =
          std::min(smallest_scale, std::sqrt(c.to_world.m[0][col] * c.to_world.m[0][col] +
                                             c.to_world.m[1][col] * c.to_world.m[1][col] +
                                             c.to_world.m[2][col] * c.to_world.m[2][col]));
    const float spread = static_cast<float>(0.5 * smallest_scale * c.object_radius);
    const std::vector<RayF> rays =
        ch04::rays_at_vertices_and_edges(placed, centre, spread, 20000, 1307);
    const long long leaks = count_misses(cpu.scene, rays);
    INFO(c.name << ": " << leaks << " leaks in " << rays.size() << " rays (< 3 / "
                << rays.size() << " if none)");
    CHECK(leaks == 0);
  }
}

TEST_CASE("a closed mesh split in two instances of one transform does not leak at the cut",
          "[ch13][watertight]") {
  // The sphere's triangles above and below a plane through its centre become two meshes, two
  // instances placed by the same transform; rays from inside aim at the edges of the cut,
  // which one triangle of each instance shares.
  //
  // Can a ray leak between them? Both instances hold the same to_object, rounded to float from
  // the same double inverse, so to_object_space makes the same float operations on the same
  // world ray: both see one and the same ray in object space, bit for bit. Both meshes hold
  // the same floats for the cut's vertices. So the two bottom-level walks test the very
  // triangles of the closed sphere against the very ray the single closed instance would, and
  // each triangle test gives the same answer in either walk: the union of their hits is the
  // closed sphere's, which cannot be empty (the test above). What is left is the top level:
  // the ray must enter the world box of the half it hits. That box is the object box placed in
  // double and widened by 16 float ulps of its largest coordinate, and the world ray at the hit
  // differs from the object ray's hit point taken back to the world by a few ulps of the
  // coordinates of the origin and the hit, which (the origin is inside the sphere) are the
  // box's. So it holds there too: 0 leaks, under the identity and under any transform in
  // range, and that is what this test asserts. (Two instances of different transforms would
  // see two different rays, and no such argument holds: a scene must not split a closed
  // surface across transforms and expect it closed.)
  for (const LeakCase& c : leak_cases()) {
    CAPTURE(c.name);
    const ch04::Mesh sphere = ch04::make_icosphere(3, {0.0, 0.0, 0.0}, c.object_radius);
    auto [top, bottom] = split_at_equator(sphere, 0.0f);
    const std::vector<std::pair<int, int>> cut = shared_edges(top, bottom);
    REQUIRE(cut.size() >= 20);
    REQUIRE(top.triangles.size() + bottom.triangles.size() == sphere.triangles.size());
    InstanceScene scene;
    scene.meshes = {top, bottom};
    scene.placements = {{c.to_world, 0}, {c.to_world, 1}};
    const CpuScene cpu(scene);
    double smallest_scale = 1e300;
    for (int col = 0; col < 3; ++col)
      smallest_scale =
          std::min(smallest_scale, std::sqrt(c.to_world.m[0][col] * c.to_world.m[0][col] +
                                             c.to_world.m[1][col] * c.to_world.m[1][col] +
                                             c.to_world.m[2][col] * c.to_world.m[2][col]));
    const Vec3f centre = c.to_world.point({0.0, 0.0, 0.0}).as<float>();
    const float spread = static_cast<float>(0.5 * smallest_scale * c.object_radius);
    const std::vector<RayF> rays =
        rays_at_edges(sphere, c.to_world, cut, centre, spread, 20000, 1308);
    const long long leaks = count_misses(cpu.scene, rays);
    // Each instance alone leaks through the cut (it is open there): the rays do aim at it.
    InstanceScene half = scene;
    half.placements.pop_back();
    const CpuScene top_only(half);
    const long long open_leaks = count_misses(top_only.scene, rays);
    WARN(c.name << ": " << leaks << " leaks in " << rays.size()
                << " rays at the cut shared by two instances (the top half alone: "
                << open_leaks << ")");
    CHECK(leaks == 0);
    CHECK(open_leaks > 1000);
  }
}

TEST_CASE(
    "a tiny instance far from the origin: hit distances against the mesh placed in double",
    "[ch13][precision]") {
  // A sphere of radius 1e-3 (scale 1e-3) at distances 1 to 1e3 from the origin, where float's
  // spacing grows to an eighth of its radius. The reference is the float ray (exact in double)
  // against the object's triangles placed in double, not rounded. The flattened copy rounds
  // every placed vertex once; the instance rounds the ray once into its space, the origin moved
  // by the translation first (to_object_space), so that no two large terms cancel. Both are
  // held to one float ulp of |position| (median), and the instanced error to at most 1.25 times
  // the flattened one (at 1 from the origin both sit at float's floor, within a few per cent of
  // each other; farther out the instance's is the smaller): moving the origin as
  // to_object.point(o) does, L^-1 o - L^-1 T in float, made it 2.5 to 3 times the flattened
  // error, which this check refuses. Both are printed.
  const ch04::Mesh object = ch04::make_icosphere(2, {0.0, 0.0, 0.0}, 1.0);
  for (const double far : {1.0, 10.0, 100.0, 1000.0}) {
    CAPTURE(far);
    std::mt19937 random(1317);
    InstanceScene scene;
    scene.meshes = {object};
    const AffineD a = translation({far, -0.5 * far, 0.3 * far}) * rotation({1, 2, 3}, 0.8) *
                      scaling({1e-3, 1e-3, 1e-3});
    scene.placements = {{a, 0}};
    const CpuScene cpu(scene);
    const ch04::Mesh flat = flatten(scene).mesh;
    std::vector<ch04::TriangleD> exact;
    for (const ch04::IndexedTriangle& t : object.triangles)
      exact.push_back({a.point(object.vertices[t.v0].as<double>()),
                       a.point(object.vertices[t.v1].as<double>()),
                       a.point(object.vertices[t.v2].as<double>())});
    const Vec3d centre = a.point({0.0, 0.0, 0.0});
    std::vector<double> instanced_error, flat_error;
    long long instanced_misses = 0, flat_misses = 0;
    for (int i = 0; i < 3000; ++i) {
      const Vec3f origin = (centre + random_unit_vector(random) * 5e-3).as<float>();
      const Vec3f target = (centre + random_unit_vector(random) * 3e-4).as<float>();
      if (origin == target) continue;
      const RayF ray{origin, target - origin};
      ch03::RayD reference_ray{origin.as<double>(), (target - origin).as<double>()};
      bool reference_hit = false;
      for (const ch04::TriangleD& t : exact) {
        const ch04::TriangleHit<double> h = ch04::intersect_watertight(reference_ray, t);
        if (h.hit) reference_ray.tmax = h.t, reference_hit = true;
      }
      if (!reference_hit) continue;
      const double length = std::sqrt(dot(reference_ray.direction, reference_ray.direction));
      const InstanceHit two = trace_instances<Query::closest>(cpu.scene.view(), ray);
      const ch04::MeshHit one =
          ch04::closest_hit(ch04::TriangleVariant::watertight, ch04::host_view(flat), ray);
      if (two.instance < 0)
        ++instanced_misses;
      else
        instanced_error.push_back(std::abs(two.t - reference_ray.tmax) * length);
      if (one.triangle < 0)
        ++flat_misses;
      else
        flat_error.push_back(std::abs(one.t - reference_ray.tmax) * length);
    }
    REQUIRE(instanced_error.size() > 1000);
    REQUIRE(flat_error.size() > 1000);
    std::sort(instanced_error.begin(), instanced_error.end());
    std::sort(flat_error.begin(), flat_error.end());
    const double instanced_median = instanced_error[instanced_error.size() / 2];
    const double flat_median = flat_error[flat_error.size() / 2];
    const double ulp = 0x1p-23 * (std::sqrt(dot(centre, centre)) + 1e-2);
    WARN("radius 1e-3 at " << far << ": hit distance error, median, instanced "
                           << instanced_median << " (" << instanced_misses
                           << " misses), flattened " << flat_median << " (" << flat_misses
                           << " misses)");
    CHECK(instanced_misses == 0);
    CHECK(flat_misses == 0);
    CHECK(instanced_median <= ulp);
    CHECK(flat_median <= ulp);
    CHECK(instanced_median <= 1.25 * flat_median);
  }
}

// ---------------------------------------------------------------------------------------------
// The moving scene

TEST_CASE("move(t) places the instances and boxes the host makes, and traces as a fresh scene",
          "[ch13][move]") {
  const Forest forest = icosphere_forest(40, 1309, 0.8);
  const std::vector<Spin>& spins = forest.spins;
  CpuScene moving(forest.scene, spins);
  const ch03::Camera<float> camera =
      ch03::make_camera<float>(*forest.scene.camera, Extent{48, 32});
  for (const double seconds : {0.0, 0.37, 2.5, -1.0}) {
    CAPTURE(seconds);
    moving.scene.move(seconds);
    const TwoLevelView view = moving.scene.view();
    REQUIRE(view.top_node_count == int(forest.scene.placements.size()) - 1);
    // Every instance as placed_instance makes it from the spin at this time; the ground
    // (no spin) as it was.
    InstanceScene at_time = forest.scene;
    for (std::size_t k = 0; k < spins.size(); ++k)
      at_time.placements[k].to_world = spin_transform(spins[k], seconds);
    std::vector<ch07::Aabb> boxes;
    for (std::size_t k = 0; k < at_time.placements.size(); ++k) {
      const Placement& p = at_time.placements[k];
      const Instance expected = placed_instance(p.to_world, p.mesh, p.mask);
      CAPTURE(k);
      REQUIRE(same_bits(view.instances[k], expected));
      boxes.push_back(world_box(moving.bottom.object_boxes[p.mesh], p.to_world));
    }
    // The boxes the top level was built over: each leaf's box in its parent's node.
    int leaves = 0;
    for (int n = 0; n < view.top_node_count; ++n)
      for (int c = 0; c < 2; ++c)
        if (view.top_nodes[n].is_leaf(c)) {
          const int id = view.top_leaf_ids[view.top_nodes[n].first[c]];
          CAPTURE(n, c, id);
          REQUIRE(same_bits(view.top_nodes[n].box[c], boxes[id]));
          ++leaves;
        }
    CHECK(leaves == int(boxes.size()));
    // A scene built from the placements at this time traces and shades the same.
    const CpuScene fresh(at_time);
    const std::vector<RayF> rays = rays_into_box(scene_box(at_time), 0.3, 2000, 1310);
    const std::vector<InstanceHit> a = trace_all(moving.scene, Query::closest, rays);
    const std::vector<InstanceHit> b = trace_all(fresh.scene, Query::closest, rays);
    long long hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      REQUIRE(same_bits(a[i], b[i]));
      hits += a[i].instance >= 0;
    }
    CHECK(hits > 200);
    std::vector<Rgba8> moved_image(48 * 32), fresh_image(48 * 32);
    render_shaded(moving.scene, camera, Extent{48, 32}, moved_image.data());
    render_shaded(fresh.scene, camera, Extent{48, 32}, fresh_image.data());
    CHECK(moved_image == fresh_image);
  }
  // The frames do differ: the trees turn.
  std::vector<Rgba8> first(48 * 32), later(48 * 32);
  moving.scene.move(0.0);
  render_shaded(moving.scene, camera, Extent{48, 32}, first.data());
  moving.scene.move(1.0);
  render_shaded(moving.scene, camera, Extent{48, 32}, later.data());
  CHECK(first != later);
}

TEST_CASE("the shaded frame writes every pixel once, where its camera ray goes",
          "[ch13][move]") {
  // Pixels go to threads in 8 x 4 tiles; an image of neither 8 nor 4 pixels' multiples has
  // tiles that hang over two edges. A pixel whose camera ray misses every instance is the
  // sky's colour, and every other pixel is not: a tile put in the wrong place fails.
  const Forest forest = icosphere_forest(40, 1309, 0.8);
  const CpuScene cpu(forest.scene);
  const Extent extent{37, 13};
  const ch03::Camera<float> camera = ch03::make_camera<float>(*forest.scene.camera, extent);
  const Rgba8 unwritten{1, 2, 3, 0};
  std::vector<Rgba8> image(static_cast<std::size_t>(extent.pixel_count()), unwritten);
  render_shaded(cpu.scene, camera, extent, image.data());
  std::vector<RayF> rays;
  for (int y = 0; y < extent.height; ++y)
    for (int x = 0; x < extent.width; ++x) rays.push_back(camera.ray_through_pixel(x, y));
  const std::vector<InstanceHit> hits = trace_all(cpu.scene, Query::closest, rays);
  const Rgba8 sky = ch03::to_rgba8(Vec3f{0.55f, 0.7f, 0.9f});
  int misses = 0;
  for (std::size_t i = 0; i < image.size(); ++i) {
    CAPTURE(i);
    REQUIRE(image[i] != unwritten);
    CHECK((image[i] == sky) == (hits[i].instance < 0));
    misses += hits[i].instance < 0;
  }
  CHECK(misses > 20); // the sky above the horizon
  CHECK(misses < int(image.size()) - 20);
}

// ---------------------------------------------------------------------------------------------
// The generated forest

TEST_CASE("make_forest: its trees stand on the ground, spaced apart", "[ch13][forest]") {
  // An icosphere above the origin, and a box off to one side whose base is not at y = 0 and
  // whose footprint is not centred: the forest must move each base centre to its place.
  const std::vector<ch04::Mesh> trees = {ch04::make_icosphere(2, {0.0, 1.0, 0.0}, 1.0),
                                         ch04::make_box({3.0, 2.0, -1.0}, {4.0, 5.0, 1.5}, 2)};
  for (const ch04::Mesh& tree : trees) {
    for (const int count : {1, 7, 150}) {
      CAPTURE(count, tree.triangles.size());
      const Forest forest = make_forest(tree, count, 1311);
      const InstanceScene& scene = forest.scene;
      REQUIRE(scene.placements.size() == std::size_t(count) + 1);
      REQUIRE(forest.spins.size() == std::size_t(count));
      REQUIRE(scene.albedo.size() == scene.placements.size());
      REQUIRE(scene.meshes.size() == 2);
      REQUIRE(scene.camera.has_value());
      const Placement& ground = scene.placements.back();
      CHECK(ground.mesh == 1);
      CHECK(same_bits(ground.to_world, AffineD{}));
      for (const Vec3f& v : scene.meshes[1].vertices) CHECK(v.y == 0.0f);
      REQUIRE_NOTHROW(make_instances(scene));

      const ch07::Aabb object = box_of(tree);
      const double width = std::max(object.hi.x - object.lo.x, object.hi.z - object.lo.z);
      const double spacing = 1.3 * width;
      std::vector<Vec3d> centres;
      for (int k = 0; k < count; ++k) {
        const Placement& p = scene.placements[k];
        CHECK(p.mesh == 0);
        CHECK(same_bits(p.to_world, spin_transform(forest.spins[k], 0.0)));
        const ch07::Aabb box = world_box(object, p.to_world);
        CAPTURE(k, box.lo.y);
        CHECK(std::abs(box.lo.y) <= 1e-4);
        // The lowest placed vertex, in double: on the ground within rounding.
        double lowest = 1e300;
        for (const Vec3f& v : tree.vertices)
          lowest = std::min(lowest, p.to_world.point(v.as<double>()).y);
        CHECK(std::abs(lowest) <= 1e-12 * spacing);
        // Within the ground's square.
        const float g = scene.meshes[1].vertices[1].x;
        CHECK(box.lo.x > -g);
        CHECK(box.hi.x < g);
        CHECK(box.lo.z > -g);
        CHECK(box.hi.z < g);
        centres.push_back((box.lo.as<double>() + box.hi.as<double>()) * 0.5);
      }
      double closest = 1e300;
      for (int i = 0; i < count; ++i)
        for (int j = i + 1; j < count; ++j) {
          const double dx = centres[i].x - centres[j].x, dz = centres[i].z - centres[j].z;
          closest = std::min(closest, std::sqrt(dx * dx + dz * dz));
        }
      CAPTURE(closest, spacing);
      CHECK(closest >= 0.8 * spacing);
    }
  }
  // The same seed makes the same forest; another seed another one.
  const ch04::Mesh tree = trees[0];
  const Forest a = make_forest(tree, 20, 5), b = make_forest(tree, 20, 5),
               c = make_forest(tree, 20, 6);
  bool same = true, other = true;
  for (int k = 0; k < 20; ++k) {
    same = same && same_bits(a.scene.placements[k].to_world, b.scene.placements[k].to_world);
    other = other && same_bits(a.scene.placements[k].to_world, c.scene.placements[k].to_world);
  }
  CHECK(same);
  CHECK_FALSE(other);
  CHECK_THAT(input_error_of([&] { make_forest(ch04::Mesh{}, 3, 1); }),
             contains("a forest needs a tree with triangles"));
}

// ---------------------------------------------------------------------------------------------
// The program

namespace {

const rt::testing::HeadlessCpuProgram run_program(RT_CH13_PROGRAM);

// The report's row named `variant`, or null.
nlohmann::json row_named(const nlohmann::json& report, const std::string& variant) {
  for (const auto& row : report["rows"])
    if (row["variant"] == variant) return row;
  return nullptr;
}

} // namespace

TEST_CASE("the wide top level finds the binary top level's hits", "[ch13][wide-top]") {
  // The same instances under chapter 07's binary walk, under chapter 09's 4-wide walk of the
  // collapsed top level nested, and under the one loop of both levels: the same closest hit
  // (instance, triangle, t bit for bit; of two at exactly the same t either may be kept) and
  // the same any-hit answer, as built and after move(); and a scene of one instance, whose
  // collapsed top level is a single leaf. The one loop visits what the nested walks visit, in
  // their order: its hits are theirs in every bit, ties included, and so are its counts.
  const Forest forest = icosphere_forest(200, 1340, 0.8);
  const BottomLevel bottom = build_bottom_level(forest.scene.meshes);
  TwoLevelScene binary(Backend::cpu, forest.scene, bottom, forest.spins, TopLayout::binary);
  TwoLevelScene nested(Backend::cpu, forest.scene, bottom, forest.spins, TopLayout::nested);
  TwoLevelScene wide(Backend::cpu, forest.scene, bottom, forest.spins, TopLayout::wide);
  const std::vector<RayF> rays = rays_into_box(scene_box(forest.scene), 0.3, 20000, 1341);
  for (const double seconds : {0.0, 2.5}) {
    binary.move(seconds);
    nested.move(seconds);
    wide.move(seconds);
    const std::vector<InstanceHit> b = trace_all(binary, Query::closest, rays);
    const std::vector<InstanceHit> n = trace_all(nested, Query::closest, rays);
    const std::vector<InstanceHit> w = trace_all(wide, Query::closest, rays);
    const std::vector<InstanceHit> b_any = trace_all(binary, Query::any, rays);
    const std::vector<InstanceHit> n_any = trace_all(nested, Query::any, rays);
    const std::vector<InstanceHit> w_any = trace_all(wide, Query::any, rays);
    long long hits = 0, ties = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      CAPTURE(seconds, i);
      REQUIRE(n[i].instance == w[i].instance);
      REQUIRE(n[i].triangle == w[i].triangle);
      REQUIRE(same_bits(n[i].t, w[i].t));
      REQUIRE(same_bits(n[i].u, w[i].u));
      REQUIRE(same_bits(n[i].v, w[i].v));
      REQUIRE(n_any[i].instance == w_any[i].instance);
      REQUIRE(n_any[i].triangle == w_any[i].triangle);
      REQUIRE((b[i].instance < 0) == (w[i].instance < 0));
      REQUIRE((b_any[i].instance < 0) == (w_any[i].instance < 0));
      REQUIRE((b[i].instance < 0) == (b_any[i].instance < 0));
      if (b[i].instance < 0) continue;
      ++hits;
      REQUIRE(same_bits(b[i].t, w[i].t));
      ties += b[i].instance != w[i].instance || b[i].triangle != w[i].triangle;
    }
    CAPTURE(hits, ties);
    CHECK(hits > 5000);
    CHECK(ties <= hits / 1000);
    // the same work, counted: every node of both levels, every instance, every triangle
    const TwoLevelView nv = nested.view(), wv = wide.view();
    for (std::size_t i = 0; i < rays.size(); i += 7) {
      TwoLevelCounters cn, cw;
      trace_two_level<Query::closest, TopLayout::nested>(nv, rays[i], 0xffffffffu, cn);
      trace_two_level<Query::closest, TopLayout::wide>(wv, rays[i], 0xffffffffu, cw);
      CAPTURE(seconds, i);
      REQUIRE(cn.top_nodes == cw.top_nodes);
      REQUIRE(cn.instances == cw.instances);
      REQUIRE(cn.bottom.nodes == cw.bottom.nodes);
      REQUIRE(cn.bottom.triangles == cw.bottom.triangles);
    }
  }
  InstanceScene one;
  one.meshes.push_back(ch04::make_icosphere(2, {0.0, 0.0, 0.0}, 1.0));
  one.placements.push_back({rotation({0.0, 1.0, 0.0}, 0.3), 0});
  const BottomLevel one_bottom = build_bottom_level(one.meshes);
  TwoLevelScene one_binary(Backend::cpu, one, one_bottom, {}, TopLayout::binary);
  const std::vector<RayF> one_rays = rays_into_box(scene_box(one), 0.5, 2000, 1342);
  const std::vector<InstanceHit> b = trace_all(one_binary, Query::closest, one_rays);
  for (const TopLayout top : {TopLayout::nested, TopLayout::wide}) {
    TwoLevelScene one_wide(Backend::cpu, one, one_bottom, {}, top);
    const std::vector<InstanceHit> w = trace_all(one_wide, Query::closest, one_rays);
    long long one_hits = 0;
    for (std::size_t i = 0; i < one_rays.size(); ++i) {
      CAPTURE(int(top), i);
      REQUIRE(b[i].triangle == w[i].triangle);
      REQUIRE(same_bits(b[i].t, w[i].t));
      one_hits += b[i].instance >= 0;
    }
    CHECK(one_hits > 200);
  }
}

TEST_CASE("the one loop honours masks and answers any-hit queries at the first hit",
          "[ch13][wide-top]") {
  // Masks: instances of mask 1 and of mask 2 in one forest; a query for mask 2 must hit only
  // instances of mask 2, and must hit exactly what the nested walk hits with the same mask.
  Forest forest = icosphere_forest(120, 1343, 0.8);
  for (std::size_t k = 0; k < forest.scene.placements.size(); ++k)
    forest.scene.placements[k].mask = k % 2 == 0 ? 1u : 2u;
  const BottomLevel bottom = build_bottom_level(forest.scene.meshes);
  TwoLevelScene nested(Backend::cpu, forest.scene, bottom, {}, TopLayout::nested);
  TwoLevelScene wide(Backend::cpu, forest.scene, bottom, {}, TopLayout::wide);
  const TwoLevelView nv = nested.view(), wv = wide.view();
  const std::vector<RayF> rays = rays_into_box(scene_box(forest.scene), 0.3, 5000, 1344);
  long long hits_of_two = 0, hits_all = 0;
  for (const RayF& ray : rays) {
    const InstanceHit a = trace_two_level<Query::closest, TopLayout::wide>(wv, ray, 2u);
    const InstanceHit b = trace_two_level<Query::closest, TopLayout::nested>(nv, ray, 2u);
    const InstanceHit all = trace_two_level<Query::closest, TopLayout::wide>(wv, ray);
    REQUIRE(a.instance == b.instance);
    REQUIRE(a.triangle == b.triangle);
    REQUIRE(same_bits(a.t, b.t));
    if (a.instance >= 0) REQUIRE(a.instance % 2 == 1);
    hits_of_two += a.instance >= 0;
    hits_all += all.instance >= 0;
    // any-hit: one loop and nested stop at the same first hit
    const InstanceHit any_a = trace_two_level<Query::any, TopLayout::wide>(wv, ray);
    const InstanceHit any_b = trace_two_level<Query::any, TopLayout::nested>(nv, ray);
    REQUIRE(any_a.instance == any_b.instance);
    REQUIRE(any_a.triangle == any_b.triangle);
  }
  CAPTURE(hits_of_two, hits_all);
  CHECK(hits_of_two > 500);
  CHECK(hits_all > hits_of_two);
}

TEST_CASE("paths through two levels: a white furnace of turned instances gives 1",
          "[ch13][paths]") {
  // Every albedo 1 under a sky of 1: each path's value is 1, or 1 / 0.95^k where roulette let
  // it live k times and 0 where it did not, so every pixel's mean is 1 in expectation, whatever
  // the instances, their transforms and the top level. The mean over the image must lie within
  // 4 standard errors of 1 (the paths' own spread, measured), for both top levels, as built and
  // with the trees turned; no pixel is NaN. A roulette that forgets to divide by q gives 0.984
  // here, which the check refuses.
  const Forest forest = icosphere_forest(40, 1350, 0.6);
  const BottomLevel bottom = build_bottom_level(forest.scene.meshes);
  const Extent extent{48, 32};
  const ch03::Camera<float> camera = ch03::make_camera<float>(*forest.scene.camera, extent);
  PathSettings settings;
  settings.samples = 64;
  settings.white = true;
  for (const TopLayout top : {TopLayout::binary, TopLayout::nested, TopLayout::wide}) {
    TwoLevelScene scene(Backend::cpu, forest.scene, bottom, forest.spins, top);
    for (const double seconds : {0.0, 1.3}) {
      scene.move(seconds);
      std::vector<Vec3f> radiance(static_cast<std::size_t>(extent.pixel_count()));
      render_paths(scene, camera, extent, settings, radiance.data(), nullptr);
      double sum = 0.0, squares = 0.0;
      for (const Vec3f& r : radiance) {
        REQUIRE(r.x == r.x);
        REQUIRE(r.x == r.y);
        REQUIRE(r.y == r.z);
        sum += r.x;
        squares += double(r.x) * r.x;
      }
      const double n = double(radiance.size());
      const double mean = sum / n;
      const double error = std::sqrt(std::max(0.0, squares / n - mean * mean) / n);
      CAPTURE(int(top), seconds, mean, error);
      CHECK(std::abs(mean - 1.0) <= 4.0 * error + 1e-6);
      CHECK(error < 0.02); // the check above is a real one
    }
  }
  // The same scene not white: every value is below the furnace's (albedos under 1 only take).
  TwoLevelScene scene(Backend::cpu, forest.scene, bottom, forest.spins);
  settings.white = false;
  std::vector<Vec3f> radiance(static_cast<std::size_t>(extent.pixel_count()));
  render_paths(scene, camera, extent, settings, radiance.data(), nullptr);
  double sum = 0.0;
  for (const Vec3f& r : radiance) sum += r.x + r.y + r.z;
  CHECK(sum / (3.0 * double(radiance.size())) < 0.9);
}

TEST_CASE("program: a small forest's report, its rows and their agreement", "[ch13][program]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch13");
  const std::string json = (folder / "forest.json").string();
  const std::string image = (folder / "forest.png").string();
  const rt::testing::ProgramRun run = run_program(
      "--instances 4 --small --width 64 --height 48 --json " + json + " --output " + image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("a forest of 4 trees of 320 triangles (icosphere)"));
  CHECK(fs::file_size(image) > 100);
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(json));
  // The top level's leaves: the 5 instances (the small trees are not opened into subtrees).
  const nlohmann::json top = row_named(report, "top-level build (LBVH over instance boxes)");
  REQUIRE(!top.is_null());
  const nlohmann::json& counted = top["metrics"];
  CHECK(counted.value("entries", counted.value("instances", 0.0)) == 5.0);
  CHECK(!row_named(report, "shaded frame: primary + shadow rays").is_null());
  for (const std::string kind : {"primary", "diffuse"}) {
    CAPTURE(kind);
    REQUIRE(!row_named(report, kind + " rays, flattened (one tree)").is_null());
    const nlohmann::json two = row_named(report, kind + " rays, two levels");
    REQUIRE(!two.is_null());
    const double same = two["metrics"]["same"], near = two["metrics"]["near"],
                 differ = two["metrics"]["differ"];
    CAPTURE(same, near, differ);
    if (kind == "primary") CHECK(same + near + differ == 64.0 * 48.0);
    CHECK(same >= 0.999 * (same + near + differ));
    CHECK(differ <= 0.001 * (same + near + differ));
  }
  // A glTF node graph, its meshes kept as instances, agrees with its flattened copy too.
  std::string gltf = std::string(RT_ASSETS_DIR) + "/instanced_shelf.gltf";
  if (!fs::exists(gltf)) gltf = std::string(RT_ASSETS_DIR) + "/material_room.gltf";
  const std::string gltf_json = (folder / "gltf.json").string();
  const rt::testing::ProgramRun scene_run =
      run_program("--scene " + gltf + " --width 48 --height 32 --frames 1 --json " + gltf_json +
                  " --output " + (folder / "gltf.png").string());
  INFO(scene_run.output);
  REQUIRE(scene_run.exit_code == 0);
  const nlohmann::json scene_report = nlohmann::json::parse(std::ifstream(gltf_json));
  const nlohmann::json primary = row_named(scene_report, "primary rays, two levels");
  REQUIRE(!primary.is_null());
  CHECK(primary["metrics"]["differ"] <= 2.0);
  CHECK(primary["metrics"]["same"] >= 0.99 * 48 * 32);
}

TEST_CASE("program: --rays and --hits number the hits as the flattened scene does",
          "[ch13][program]") {
  // The program's scene made here from the same options: its hits through both levels, in
  // process, are the hit file's bit for bit, with instance k's triangle t numbered
  // first_triangle[k] + t; and they agree with brute force over the flattened mesh.
  InstancingOptions options;
  options.instances = 6;
  options.small = true;
  std::vector<Spin> spins;
  const InstanceScene scene = make_scene(options, spins);
  REQUIRE(scene.placements.size() == 7);
  const Flattened flat = flatten(scene);
  const std::vector<RayF> rays = rays_into_box(scene_box(scene), 0.4, 3000, 1312);
  const fs::path folder = rt::testing::temp_folder("rt_ch13");
  const std::string ray_file = (folder / "forest.rays").string();
  const std::string hit_file = (folder / "forest.hits").string();
  ch07::write_ray_file(ray_file, rays);
  fs::remove(hit_file);
  const rt::testing::ProgramRun run =
      run_program("--instances 6 --small --rays " + ray_file + " --hits " + hit_file);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const std::vector<ch04::MeshHit> hits = ch07::read_hit_file(hit_file);
  REQUIRE(hits.size() == rays.size());
  const CpuScene cpu(scene, spins);
  const std::vector<InstanceHit> expected = trace_all(cpu.scene, Query::closest, rays);
  const std::vector<ch04::MeshHit> reference = brute_force(flat.mesh, rays);
  long long hit_count = 0, same = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    CAPTURE(i);
    REQUIRE(hits[i].triangle == flat_id(flat, expected[i]));
    REQUIRE(same_bits(hits[i].t, expected[i].t));
    hit_count += hits[i].triangle >= 0;
    same += hits[i].triangle == reference[i].triangle;
  }
  CAPTURE(hit_count, same);
  CHECK(hit_count > 500);
  CHECK(same >= 0.999 * double(rays.size()));
}

TEST_CASE("program: --dump-hits writes the view's camera rays' hits, numbered as flattened",
          "[ch13][program]") {
  // The camera rays of the program's own view (the forest's camera, 40 x 30 pixels) traced in
  // process through both levels: the dump is those hits, bit for bit, numbered instance by
  // instance; and the diffuse dump has one record per primary hit.
  InstancingOptions options;
  options.instances = 6;
  options.small = true;
  std::vector<Spin> spins;
  const InstanceScene scene = make_scene(options, spins);
  const Flattened flat = flatten(scene);
  const Extent extent{40, 30};
  const ch03::Camera<float> camera = ch03::make_camera<float>(*scene.camera, extent);
  std::vector<RayF> rays;
  for (int y = 0; y < extent.height; ++y)
    for (int x = 0; x < extent.width; ++x) rays.push_back(camera.ray_through_pixel(x, y));
  const CpuScene cpu(scene, spins);
  const std::vector<InstanceHit> expected = trace_all(cpu.scene, Query::closest, rays);
  const fs::path folder = rt::testing::temp_folder("rt_ch13");
  const std::string primary_file = (folder / "view.hits").string();
  const std::string diffuse_file = (folder / "diffuse.hits").string();
  fs::remove(primary_file);
  fs::remove(diffuse_file);
  const rt::testing::ProgramRun run =
      run_program("--instances 6 --small --width 40 --height 30 --dump-hits " + primary_file);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const std::vector<ch04::MeshHit> hits = ch07::read_hit_file(primary_file);
  REQUIRE(hits.size() == rays.size());
  long long hit_count = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    CAPTURE(i);
    REQUIRE(hits[i].triangle == flat_id(flat, expected[i]));
    REQUIRE(same_bits(hits[i].t, expected[i].t));
    hit_count += hits[i].triangle >= 0;
  }
  CHECK(hit_count > 100);
  const rt::testing::ProgramRun diffuse_run =
      run_program("--instances 6 --small --width 40 --height 30 --dump-hits " + diffuse_file +
                  " --ray-type diffuse");
  INFO(diffuse_run.output);
  REQUIRE(diffuse_run.exit_code == 0);
  CHECK(static_cast<long long>(ch07::read_hit_file(diffuse_file).size()) <= hit_count);
  CHECK(static_cast<long long>(ch07::read_hit_file(diffuse_file).size()) > hit_count / 2);
}

TEST_CASE("program: bad input is refused with one line", "[ch13][program]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch13");
  const std::string rays = (folder / "one.rays").string();
  const RayF one[] = {{{0.0f, 1.0f, -10.0f}, {0.0f, 0.0f, 1.0f}}};
  ch07::write_ray_file(rays, one);
  const rt::testing::RefusedInput cases[] = {
      {"--instances 0", 2, "--instances"},
      {"--instances 16777216 --small", 2, "--instances"},
      {"--rays " + rays, 2, "--rays and --hits go together"},
      {"--hits " + (folder / "h.hits").string(), 2, "--rays and --hits go together"},
      {"--small --scene x.obj", 2, "--small makes its own trees: not with --scene"},
      {"--small --ray-type diffuse", 2, "--ray-type goes with --dump-hits"},
      {"--small --ray-type sideways --dump-hits x.hits", 2, "--ray-type"},
      {"--scene " + (folder / "missing.obj").string(), 1, "missing.obj"},
      {"--scene " + (folder / "missing.gltf").string(), 1, "missing.gltf"},
      {"--small --rays " + (folder / "missing.rays").string() + " --hits " +
           (folder / "h.hits").string(),
       1, "missing.rays"},
  };
  rt::testing::check_refused(run_program, cases);
}
