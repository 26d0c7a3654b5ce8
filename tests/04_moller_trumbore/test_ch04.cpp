// Chapter 04 tests on the CPU: exact answers for simple rays, the stiff cases of the triangle
// test (tiny, degenerate, in-plane, NaN), generated meshes, and leaks through closed meshes.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "rt_catch.h"

#include "adversarial_rays.h"
#include "leak_configurations.h"
#include "mesh_gen.h"
#include "mesh_render.h"
#include "triangle_cases.h"
#include "triangles.h"

using namespace rt;
using namespace rt::ch04;

namespace {

template <class T> void check_analytic_hits() {
  const auto ray = [](Vec3d origin, Vec3d direction,
                      double tmax = std::numeric_limits<double>::infinity()) {
    return Ray<T>{origin.as<T>(), direction.as<T>(), T(0), T(tmax)};
  };
  // Counter-clockwise seen from +z: z > 0 is the front, z < 0 the back.
  const Triangle<T> tri{{T(0), T(0), T(0)}, {T(1), T(0), T(0)}, {T(0), T(1), T(0)}};
  for (const TriangleVariant variant : k_variants) {
    CAPTURE(to_string(variant));
    const TriangleHit<T> back =
        intersect_triangle(variant, ray({0.25, 0.5, -2}, {0, 0, 1}), tri);
    REQUIRE(back.hit);
    CHECK(back.t == T(2));
    CHECK(back.u == T(0.25));
    CHECK(back.v == T(0.5));
    // From the front, with a direction of length 4: t is in units of the direction.
    const TriangleHit<T> front =
        intersect_triangle(variant, ray({0.5, 0.25, 3}, {0, 0, -4}), tri);
    REQUIRE(front.hit);
    CHECK(front.t == T(0.75));
    CHECK(front.u == T(0.5));
    CHECK(front.v == T(0.25));
    // A slanted triangle and direction: x + y + z = 3 hit at (1, 1, 1).
    const Triangle<T> slanted{{T(3), T(0), T(0)}, {T(0), T(3), T(0)}, {T(0), T(0), T(3)}};
    const TriangleHit<T> diagonal =
        intersect_triangle(variant, ray({0, 0, 0}, {1, 1, 1}), slanted);
    REQUIRE(diagonal.hit);
    const double ulps = 4 * std::numeric_limits<T>::epsilon();
    CHECK(diagonal.t == Approx(1.0).epsilon(ulps));
    CHECK(diagonal.u == Approx(1.0 / 3).epsilon(ulps));
    CHECK(diagonal.v == Approx(1.0 / 3).epsilon(ulps));
    // Misses: beside the triangle, behind the origin, beyond tmax.
    CHECK_FALSE(intersect_triangle(variant, ray({0.75, 0.5, -2}, {0, 0, 1}), tri).hit);
    CHECK_FALSE(intersect_triangle(variant, ray({0.25, 0.5, -2}, {0, 0, -1}), tri).hit);
    CHECK_FALSE(intersect_triangle(variant, ray({0.25, 0.5, -2}, {0, 0, 1}, 1.5), tri).hit);
  }
}

} // namespace

TEST_CASE("analytic hits: t, u and v exact, front and back faces", "[ch04]") {
  check_analytic_hits<float>();
  check_analytic_hits<double>();
}

namespace {

// Where the ray's line crosses the triangle's plane, in float64 from the float inputs: the
// smallest of its three barycentric coordinates. Positive inside, negative outside, and its
// size says how far inside or outside, as a fraction of the triangle.
double smallest_barycentric(RayF ray, TriangleF tri) {
  const Vec3d v0 = tri.v0.as<double>(), e1 = tri.v1.as<double>() - v0,
              e2 = tri.v2.as<double>() - v0, d = ray.direction.as<double>();
  const Vec3d normal = cross(e1, e2);
  const Vec3d p = ray.origin.as<double>() - v0 +
                  d * (dot(v0 - ray.origin.as<double>(), normal) / dot(d, normal));
  const double area = dot(normal, normal);
  const double u = dot(cross(p, e2), normal) / area, v = dot(cross(e1, p), normal) / area;
  return std::min({u, v, 1 - u - v});
}

} // namespace

TEST_CASE("tiny triangles at unit distance hit as the float64 reference does", "[ch04]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), barycentric(-0.25f, 1.25f);
  for (const float leg : {1e-3f, 1e-4f, 1e-5f, 1e-6f}) {
    // A float ray direction resolves about an ulp of the unit distance, so the float tests
    // see the triangle's border only to eps/leg in barycentrics: rays that close to the
    // border may go either way (measured: within 0.75 eps/leg). Those within 2 eps/leg are
    // left out of the comparison.
    const double border_band = 2 * std::numeric_limits<float>::epsilon() / leg;
    long long compared = 0, hits = 0, mismatches = 0;
    float largest_hit_det = 0;
    for (int n = 0; n < 20'000; ++n) {
      // A randomly oriented right triangle with legs `leg`, one unit from the ray's origin.
      const Vec3f centre = normalize(Vec3f{unit(rng), unit(rng), unit(rng)});
      const Vec3f leg_a = normalize(cross(centre, Vec3f{unit(rng), unit(rng), unit(rng)}));
      const Vec3f leg_b = cross(centre, leg_a);
      const TriangleF tri{centre, centre + leg_a * leg, centre + leg_b * leg};
      const Vec3f target =
          tri.v0 + (tri.v1 - tri.v0) * barycentric(rng) + (tri.v2 - tri.v0) * barycentric(rng);
      const RayF ray{{0, 0, 0}, normalize(target)};
      const double border = smallest_barycentric(ray, tri);
      if (std::abs(border) <= border_band) continue;
      ++compared;
      hits += border > 0;
      for (const TriangleVariant variant : k_variants)
        mismatches += intersect_triangle(variant, ray, tri).hit != (border > 0);
      if (border > 0) {
        const float det = dot(tri.v1 - tri.v0, cross(ray.direction, tri.v2 - tri.v0));
        largest_hit_det = std::max(largest_hit_det, std::abs(det));
      }
    }
    CAPTURE(leg, compared, hits, mismatches, largest_hit_det);
    CHECK(hits >= 100);
    CHECK(mismatches == 0);
    // det = e1 . (d x e2) is about leg^2 here (the float vertices sit up to 6% off at 1e-6):
    // an absolute cull |det| < 1e-6, a common textbook epsilon, would reject them (every
    // one from legs of 1e-4 down).
    CHECK(largest_hit_det <= 1.2f * leg * leg);
  }
}

TEST_CASE("degenerate triangles: no NaN, and no hit but watertight's rounded sliver",
          "[ch04]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), along(-0.5f, 2.5f);
  const Vec3f p{0.5f, -0.25f, 2.0f}, e{0.25f, 0.5f, -0.125f}; // exact: 2e and 3e too
  struct Degenerate {
    TriangleF tri;
    bool collinear; // three distinct points on a line, else a repeated vertex
  };
  const Degenerate cases[] = {{{p, p + e, p + e * 2.0f}, true},
                              {{p, p + e * 3.0f, p + e}, true},
                              {{p, p, p + e}, false},
                              {{p, p + e, p + e}, false},
                              {{p, p, p}, false}};
  long long sliver_hits = 0;
  for (const Degenerate& degenerate : cases) {
    for (int n = 0; n < 20'000; ++n) {
      // Aimed at the segment's line, from random origins near it.
      const Vec3f origin{unit(rng) * 4, unit(rng) * 4, unit(rng) * 4};
      const RayF ray{origin, p + e * along(rng) - origin};
      CAPTURE(degenerate.collinear, n);
      // Möller–Trumbore's determinant is exactly 0 for all of them.
      const TriangleHitF moller_trumbore = intersect_moller_trumbore(ray, degenerate.tri);
      REQUIRE_FALSE(moller_trumbore.hit);
      REQUIRE(!std::isnan(moller_trumbore.t));
      // The watertight test sees the vertices after v - o and the shear, both rounded, and
      // three collinear points can round to a sliver a few ulps wide. Hitting it is right: in
      // a closed mesh that sliver is what fills the crack between its rounded neighbours. A
      // repeated vertex stays repeated, and its edge functions cancel exactly.
      const TriangleHitF watertight = intersect_watertight(ray, degenerate.tri);
      REQUIRE(!std::isnan(watertight.t));
      if (watertight.hit) {
        REQUIRE(degenerate.collinear);
        REQUIRE(std::isfinite(watertight.t));
        const Vec3f hit_point = ray.origin + ray.direction * watertight.t;
        const Vec3f from_p = hit_point - p;
        REQUIRE(length(from_p - e * (dot(from_p, e) / dot(e, e))) <= 1e-5f); // on the line
        ++sliver_hits;
      }
    }
  }
  std::printf("degenerate triangles: watertight hit the rounded sliver of a collinear "
              "triangle %lld times in 40000 rays\n",
              sliver_hits);
}

TEST_CASE("rays in the triangle's plane or grazing it: a miss or a finite t", "[ch04]") {
  const TriangleF tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (const TriangleVariant variant : k_variants) {
    CAPTURE(to_string(variant));
    CHECK_FALSE(intersect_triangle(variant, RayF{{-1, 0.25f, 0}, {1, 0, 0}}, tri).hit);
    CHECK_FALSE(intersect_triangle(variant, RayF{{-1, -1, 0}, {1, 1, 0}}, tri).hit);
    CHECK_FALSE(intersect_triangle(variant, RayF{{0.25f, 0.25f, 0}, {0, 1, 0}}, tri).hit);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), exponent(-45.0f, -1.0f);
    for (int n = 0; n < 100'000; ++n) {
      // Nearly in the plane: a z component from 1e-1 down to the denormals.
      const float z = std::copysign(std::pow(10.0f, exponent(rng)), unit(rng));
      const RayF ray{{unit(rng), unit(rng), -z * unit(rng)}, {unit(rng), unit(rng), z}};
      const TriangleHitF hit = intersect_triangle(variant, ray, tri);
      CAPTURE(n, z);
      if (hit.hit) REQUIRE(std::isfinite(hit.t));
      REQUIRE(!std::isnan(hit.t));
    }
  }
}

TEST_CASE("NaN or infinity in the ray is a miss", "[ch04]") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const TriangleF tri{{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  const RayF bad_rays[] = {{{nan, 0, -1}, {0, 0, 1}},     {{0, 0, -1}, {0, nan, 1}},
                           {{0, 0, -inf}, {0, 0, 1}},     {{0, 0, -1}, {0, 0, inf}},
                           {{0, 0, -1}, {inf, 0, inf}},   {{0, 0, -1}, {0, 0, 0}},
                           {{0, 0, -1}, {nan, nan, nan}}, {{inf, inf, inf}, {-1, -1, -1}}};
  for (const TriangleVariant variant : k_variants) {
    for (const RayF& ray : bad_rays) {
      CAPTURE(to_string(variant), ray.origin.x, ray.origin.z, ray.direction.x, ray.direction.z);
      CHECK_FALSE(intersect_triangle(variant, ray, tri).hit);
    }
  }
}

TEST_CASE("generated meshes are closed and face outwards", "[ch04]") {
  const auto signed_volume = [](const Mesh& mesh) {
    double volume = 0; // divergence theorem: sum of v0 . (v1 x v2) / 6
    for (int i = 0; i < int(mesh.triangles.size()); ++i) {
      const TriangleF t = mesh.triangle(i);
      volume += dot(t.v0.as<double>(), cross(t.v1.as<double>(), t.v2.as<double>())) / 6;
    }
    return volume;
  };
  for (int subdivisions = 0; subdivisions <= 3; ++subdivisions) {
    const Mesh sphere = make_icosphere(subdivisions, {0, 0, 0}, 2.0);
    CAPTURE(subdivisions);
    CHECK(sphere.triangles.size() == 20u << (2 * subdivisions));
    CHECK(count_unpaired_edges(sphere) == 0);
    CHECK(sphere.vertices.size() == sphere.triangles.size() / 2 + 2); // Euler: V - E + F = 2
    const double ball_volume = 4.0 / 3.0 * std::numbers::pi * 8;      // inscribed in the ball
    CHECK(signed_volume(sphere) > 0.6 * ball_volume);
    CHECK(signed_volume(sphere) < ball_volume);
  }
  for (int cells = 1; cells <= 4; ++cells) {
    const Mesh box = make_box({-1, -2, -3}, {1, 2, 3}, cells);
    CAPTURE(cells);
    CHECK(box.triangles.size() == 12u * cells * cells);
    CHECK(count_unpaired_edges(box) == 0);
    CHECK(signed_volume(box) == Approx(2.0 * 4.0 * 6.0).epsilon(1e-12));
  }
  Mesh open = make_box({0, 0, 0}, {1, 1, 1}, 2);
  open.triangles.pop_back();
  CHECK(count_unpaired_edges(open) == 3);
}

TEST_CASE("closest hit from the centre of a box lies on the box", "[ch04]") {
  const Mesh box = make_box({-1, -1, -1}, {1, 1, 1}, 3);
  const std::vector<RayF> rays = rays_at_vertices_and_edges(box, {0, 0, 0}, 0.0f, 10'000, 8);
  const TriangleVariant variant = TriangleVariant::watertight; // no leaks to skip
  const std::vector<MeshHit> hits = closest_hits_cpu(variant, box, rays);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    CAPTURE(i);
    REQUIRE(hits[i].triangle >= 0);
    const Vec3f p = rays[i].origin + rays[i].direction * hits[i].t;
    REQUIRE(max_component(elementwise_abs(p)) == Approx(1.0f).epsilon(1e-6));
    // Closest: no triangle accepts the ray nearer than the one reported.
    const RayF nearer{rays[i].origin, rays[i].direction, 0.0f, hits[i].t};
    REQUIRE(closest_hit(variant, host_view(box), nearer).triangle == -1);
  }
}

TEST_CASE("rays from inside closed meshes, aimed at vertices and edges: watertight never "
          "leaks, Moller-Trumbore does",
          "[ch04][slow]") {
  constexpr int k_rays = 1'000'000;
  long long moller_trumbore_leaks = 0;
  for (const auto& configuration : k_leak_configurations) {
    const Mesh mesh = configuration.make_mesh();
    const std::vector<RayF> rays = rays_at_vertices_and_edges(
        mesh, configuration.inside(), configuration.spread, k_rays, configuration.seed);
    for (const TriangleVariant variant : k_variants) {
      const auto start = std::chrono::steady_clock::now();
      const LeakCount count = count_leaks_cpu(variant, mesh, rays);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("%-28s %-16s %lld rays: %lld leaks, %lld double hits (%.1f s)\n",
                  configuration.name, to_string(variant), count.rays, count.leaks,
                  count.double_hits, seconds);
      CAPTURE(configuration.name, to_string(variant), count.leaks, count.double_hits);
      CHECK(count.non_finite == 0);
      CHECK(count.rays == k_rays);
      if (variant == TriangleVariant::watertight)
        CHECK(count.leaks == 0);
      else
        moller_trumbore_leaks += count.leaks;
    }
  }
  CHECK(moller_trumbore_leaks > 0); // the test shows the problem it guards against
}

TEST_CASE("demo scene: closed icosphere and box, a floor quad, each triangle labelled",
          "[ch04]") {
  const ch04::TriangleScene scene = ch04::make_demo_scene(2, {0, 0, 0});
  REQUIRE(scene.object.size() == scene.mesh.triangles.size());
  CHECK(scene.mesh.triangles.size() == 320 + 48 + 2);
  ch04::Mesh parts[2];
  for (std::size_t i = 0; i < scene.object.size(); ++i)
    if (scene.object[i] < 2)
      parts[scene.object[i]].triangles.push_back(scene.mesh.triangles[i]);
  for (ch04::Mesh& part : parts) {
    part.vertices = scene.mesh.vertices;
    CHECK(ch04::count_unpaired_edges(part) == 0);
  }
}

TEST_CASE("demo scene render: no holes against float64, at the origin and moved by 1e5",
          "[ch04]") {
  const Extent extent{200, 112};
  for (double offset : {0.0, 1e5}) {
    const Vec3d shift{offset, offset, offset};
    const ch04::TriangleScene scene = ch04::make_demo_scene(2, shift);
    const ch03::CameraSpec spec = rt::testing::demo_scene_camera(shift);
    const ch04::MeshReference reference = ch04::render_triangles_reference(scene, spec, extent);
    for (TriangleVariant variant : k_variants) {
      Image image(extent.width, extent.height);
      std::vector<ch04::MeshPixelRecord> records(image.pixels.size());
      ch04::render_triangles(Backend::cpu, variant, ch04::host_view(scene.mesh),
                             scene.object.data(), ch03::make_camera<float>(spec, extent),
                             extent, image.pixels.data(), records.data());
      const ch04::MeshFrameError e = ch04::compare_with_reference(image, records, reference);
      CAPTURE(offset, ch04::to_string(variant), e.pixels_differing, e.holes);
      CHECK(e.nan_pixels == 0);
      if (variant == TriangleVariant::watertight) CHECK(e.holes == 0);
      CHECK(e.pixels_differing <= extent.pixel_count() / 100);
    }
  }
}

TEST_CASE("the watertight test with its axes fixed at compile time gives the run-time axes' "
          "answer, bit for bit, in all six cases",
          "[ch04]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  const auto same = [](const TriangleHitF& a, const TriangleHitF& b) {
    return a.hit == b.hit &&
           (!a.hit || (std::bit_cast<unsigned>(a.t) == std::bit_cast<unsigned>(b.t) &&
                       std::bit_cast<unsigned>(a.u) == std::bit_cast<unsigned>(b.u) &&
                       std::bit_cast<unsigned>(a.v) == std::bit_cast<unsigned>(b.v)));
  };
  int cases_seen[9] = {}, hits = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const TriangleF tri{{unit(rng), unit(rng), unit(rng)},
                        {unit(rng), unit(rng), unit(rng)},
                        {unit(rng), unit(rng), unit(rng)}};
    const Vec3f origin{3 * unit(rng), 3 * unit(rng), 3 * unit(rng)};
    const Vec3f toward = (tri.v0 + tri.v1 + tri.v2) * (1.0f / 3.0f) - origin;
    const Vec3f jitter{unit(rng), unit(rng), unit(rng)};
    const RayF ray{origin, trial % 2 ? toward : toward + 0.3f * jitter, 0.0f, 1e30f};
    const WatertightRay<float> frame = watertight_ray(ray);
    const TriangleHitF expected = intersect_watertight(ray, tri);
    const TriangleHitF fixed = with_fixed_axes(
        frame, [&](auto axes) { return intersect_watertight(frame, tri, axes); });
    CAPTURE(trial, frame.kx, frame.ky, frame.kz);
    const int key = frame.kz * 3 + frame.kx;
    REQUIRE((key == 1 || key == 2 || key == 3 || key == 5 || key == 6 || key == 7));
    REQUIRE(frame.kx + frame.ky + frame.kz == 3); // a permutation of 0, 1, 2
    CHECK(same(fixed, expected));
    ++cases_seen[key];
    hits += expected.hit;
  }
  for (const int c : {1, 2, 3, 5, 6, 7}) CHECK(cases_seen[c] > 1000); // every case met
  CHECK(hits > 5000);
}
