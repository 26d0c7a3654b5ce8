// Chapter 03 tests on the CPU: exact answers for simple rays, the stiff cases of the sphere
// test (small and far, huge and close, tangent, NaN), the cameras, and spawned rays.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "rt_catch.h"

#include "camera.h"
#include "spawn.h"
#include "sphere.h"
#include "sphere_cases.h"
#include "spheres.h"

using namespace rt;
using namespace rt::ch03;
using rt::testing::distance_to_ray_line;
using rt::testing::far_sphere_case;
using rt::testing::ground_sphere_case;
using rt::testing::stable_silhouette_band;

namespace {

constexpr SphereVariant k_variants[] = {SphereVariant::textbook, SphereVariant::stable};

template <class T> void check_axis_rays_hit_exactly() {
  const Sphere<T> unit_sphere{{T(0), T(0), T(0)}, T(1)};
  for (const SphereVariant variant : k_variants) {
    for (const T distance : {T(2), T(3), T(5), T(10), T(100), T(4096)}) {
      CAPTURE(to_string(variant), distance);
      const Ray<T> ray{{T(0), T(0), -distance}, {T(0), T(0), T(1)}};
      const SphereHit<T> hit = intersect_sphere(variant, ray, unit_sphere);
      REQUIRE(hit.hit);
      CHECK(hit.t == distance - T(1));
      // A direction of length 2 halves t: t is measured in units of the direction.
      const Ray<T> long_direction{{-distance, T(0), T(0)}, {T(2), T(0), T(0)}};
      CHECK(intersect_sphere(variant, long_direction, unit_sphere).t ==
            (distance - T(1)) / T(2));
    }
  }
}

} // namespace

TEST_CASE("a ray along an axis hits a unit sphere at distance minus radius, exactly",
          "[ch03]") {
  check_axis_rays_hit_exactly<float>();
  check_axis_rays_hit_exactly<double>();
}

TEST_CASE("from inside the sphere the hit is the far root", "[ch03]") {
  for (const SphereVariant variant : k_variants) {
    CAPTURE(to_string(variant));
    const SphereF sphere{{0.0f, 0.0f, 0.0f}, 2.0f};
    CHECK(intersect_sphere(variant, RayF{{0, 0, 0}, {1, 0, 0}}, sphere).t == 2.0f);
    CHECK(intersect_sphere(variant, RayF{{1, 0, 0}, {1, 0, 0}}, sphere).t == 1.0f);
    CHECK(intersect_sphere(variant, RayF{{1, 0, 0}, {-1, 0, 0}}, sphere).t == 3.0f);
    CHECK(intersect_sphere(variant, RayF{{0, 0, 0}, {0, 0, -4}}, sphere).t == 0.5f);
  }
}

TEST_CASE("origin on the surface: leaving misses, entering hits the far side", "[ch03]") {
  const SphereF sphere{{0.0f, 0.0f, 0.0f}, 1.0f};
  for (const SphereVariant variant : k_variants) {
    CAPTURE(to_string(variant));
    CHECK_FALSE(intersect_sphere(variant, RayF{{1, 0, 0}, {1, 0, 0}}, sphere).hit);
    CHECK_FALSE(intersect_sphere(variant, RayF{{0, -1, 0}, {0, -3, 0}}, sphere).hit);
    const SphereHitF entering = intersect_sphere(variant, RayF{{1, 0, 0}, {-1, 0, 0}}, sphere);
    REQUIRE(entering.hit);
    CHECK(entering.t == 2.0f);
    // Leaving along the tangent plane: the double root is t = 0, outside (tmin, tmax).
    CHECK_FALSE(intersect_sphere(variant, RayF{{1, 0, 0}, {0, 1, 0}}, sphere).hit);
  }
}

TEST_CASE("tangent rays hit at the tangent point or miss cleanly, never NaN", "[ch03]") {
  const SphereF sphere{{0.0f, 0.0f, 0.0f}, 1.0f};
  for (const SphereVariant variant : k_variants) {
    CAPTURE(to_string(variant));
    const SphereHitF exact = intersect_sphere(variant, RayF{{1, 0, -5}, {0, 0, 1}}, sphere);
    REQUIRE(exact.hit);
    CHECK(exact.t == 5.0f);
    // Offsets a few ulps either side of the tangent line, in several directions.
    float offset = 1.0f;
    for (int i = 0; i < 8; ++i) offset = std::nextafter(offset, 0.0f);
    for (int step = 0; step < 16; ++step, offset = std::nextafter(offset, 2.0f)) {
      for (const Vec3f axis : {Vec3f{1, 0, 0}, Vec3f{0, -1, 0}, normalize(Vec3f{1, 1, 0})}) {
        const SphereHitF hit =
            intersect_sphere(variant, RayF{axis * offset + Vec3f{0, 0, -5}, {0, 0, 1}}, sphere);
        CAPTURE(offset, axis.x, axis.y);
        CHECK(!std::isnan(hit.t));
        if (hit.hit) CHECK((hit.t > 4.9f && hit.t <= 5.0f));
      }
    }
  }
}

TEST_CASE("NaN or infinity anywhere in the ray is a miss", "[ch03]") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const SphereF sphere{{0.0f, 0.0f, 0.0f}, 1.0f};
  const std::vector<RayF> bad_rays = {
      {{nan, 0, -5}, {0, 0, 1}},       {{0, 0, -5}, {0, nan, 1}},    {{0, 0, -inf}, {0, 0, 1}},
      {{0, 0, -5}, {0, 0, inf}},       {{0, 0, -5}, {inf, 0, inf}},  {{0, 0, -5}, {0, 0, 0}},
      {{inf, inf, inf}, {-1, -1, -1}}, {{0, 0, -5}, {nan, nan, nan}}};
  for (const SphereVariant variant : k_variants) {
    for (std::size_t i = 0; i < bad_rays.size(); ++i) {
      CAPTURE(to_string(variant), i);
      const SphereHitF hit = intersect_sphere(variant, bad_rays[i], sphere);
      CHECK_FALSE(hit.hit);
    }
    CHECK_FALSE(intersect_sphere(variant, RayF{{0, 0, -5}, {0, 0, 1}}, SphereF{{}, nan}).hit);
  }
}

TEST_CASE("small sphere far away: stable hits iff float64 says so, textbook does not",
          "[ch03]") {
  constexpr int k_rays = 100'000;
  for (const float distance : {1e3f, 1e4f, 1e5f}) {
    const auto [sphere, rays] = far_sphere_case(distance, k_rays, 1234);
    long long outside_band = 0, stable_wrong = 0, textbook_wrong = 0;
    for (const RayF& ray : rays) {
      const double miss_distance = distance_to_ray_line(ray, sphere) - sphere.radius;
      if (std::abs(miss_distance) <= stable_silhouette_band(ray, sphere)) continue;
      ++outside_band;
      const bool reference_hit = miss_distance < 0;
      stable_wrong += intersect_sphere_stable(ray, sphere).hit != reference_hit;
      textbook_wrong += intersect_sphere_textbook(ray, sphere).hit != reference_hit;
    }
    std::printf("far sphere at %g radii: %lld of %d rays outside the band; false hits or "
                "misses: stable %lld, textbook %lld\n",
                double(distance), outside_band, k_rays, stable_wrong, textbook_wrong);
    CAPTURE(distance, outside_band, stable_wrong, textbook_wrong);
    CHECK(outside_band > k_rays * 8 / 10);
    CHECK(stable_wrong == 0);
    CHECK(textbook_wrong > 0); // the test shows the problem it guards against
  }
}

TEST_CASE("huge sphere seen from close by: stable near root within 1e-6 of float64", "[ch03]") {
  for (const float radius : {1e4f, 1e5f, 1e6f}) {
    const auto [sphere, rays] = ground_sphere_case(radius, 100'000, 99);
    double stable_worst = 0, textbook_worst = 0;
    for (const RayF& ray : rays) {
      const RayD ray_d = ray_as<double>(ray);
      const SphereD sphere_d{sphere.centre.as<double>(), double(sphere.radius)};
      const SphereHitD reference = intersect_sphere_stable(ray_d, sphere_d);
      REQUIRE(reference.hit);
      // The two float64 forms agree: the reference does not lean on the method under test.
      REQUIRE(std::abs(intersect_sphere_textbook(ray_d, sphere_d).t - reference.t) <=
              1e-9 * reference.t);
      const SphereHitF stable = intersect_sphere_stable(ray, sphere);
      const SphereHitF textbook = intersect_sphere_textbook(ray, sphere);
      REQUIRE(stable.hit);
      stable_worst = std::max(stable_worst, std::abs(stable.t - reference.t) / reference.t);
      textbook_worst =
          std::max(textbook_worst,
                   textbook.hit ? std::abs(textbook.t - reference.t) / reference.t : 1.0);
    }
    std::printf("ground sphere of radius %g, eye 1..10 above: worst relative t error: "
                "stable %.2e, textbook %.2e\n",
                double(radius), stable_worst, textbook_worst);
    CAPTURE(radius, stable_worst, textbook_worst);
    CHECK(stable_worst <= 1e-6);
    CHECK(textbook_worst > 1e-4);
  }
}

namespace {

// The benchmark views (book appendix A) plus one looking straight down the z axis.
struct View {
  Vec3d eye, target;
  double vfov_degrees;
};
constexpr View k_views[] = {{{-300, 400, 300}, {1000, 100, -700}, 60}, // conference
                            {{-14, 3, 0}, {10, 5, 0}, 60},             // sponza
                            {{0.5, -0.25, 8}, {0.5, -0.25, 0}, 45}};   // down -z

// The benchmark formula, written out again in float64 with plain operations.
Vec3d benchmark_direction(const View& view, int width, int height, int i, int j) {
  const Vec3d forward = normalize(view.target - view.eye);
  const Vec3d right = normalize(cross(forward, Vec3d{0, 1, 0}));
  const Vec3d up = cross(right, forward);
  const double tan_half = std::tan(view.vfov_degrees * std::numbers::pi / 180 / 2);
  const double sx = (2 * (i + 0.5) / width - 1) * tan_half * (double(width) / height);
  const double sy = (1 - 2 * (j + 0.5) / height) * tan_half;
  return normalize(right * sx + up * sy + forward);
}

template <class T> PinholeCamera<T> camera_for(const View& view, int width, int height) {
  return make_pinhole_camera(view.eye.as<T>(), view.target.as<T>(), Vec3<T>{0, 1, 0},
                             T(view.vfov_degrees), width, height);
}

} // namespace

TEST_CASE("pinhole: the centre pixel of an odd-size image looks at the target", "[ch03]") {
  for (const View& view : k_views) {
    for (const auto& [width, height] :
         {std::pair{1921, 1081}, std::pair{33, 33}, std::pair{5, 101}}) {
      CAPTURE(view.eye.x, width, height);
      const Vec3d towards_target = normalize(view.target - view.eye);
      const RayD ray_d =
          camera_for<double>(view, width, height).ray_through_pixel(width / 2, height / 2);
      CHECK(ray_d.origin == view.eye);
      CHECK(length(ray_d.direction - towards_target) <=
            4 * std::numeric_limits<double>::epsilon());
      const RayF ray_f =
          camera_for<float>(view, width, height).ray_through_pixel(width / 2, height / 2);
      // The float camera starts from the float-rounded eye and target.
      const Vec3d towards_rounded_target =
          normalize(view.target.as<float>().as<double>() - view.eye.as<float>().as<double>());
      CHECK(length(ray_f.direction.as<double>() - towards_rounded_target) <=
            4 * std::numeric_limits<float>::epsilon());
    }
  }
}

TEST_CASE("pinhole: corner rays follow the benchmark formula", "[ch03]") {
  constexpr int width = 1920, height = 1080;
  for (const View& view : k_views) {
    const PinholeCamera<double> camera_d = camera_for<double>(view, width, height);
    const PinholeCamera<float> camera_f = camera_for<float>(view, width, height);
    for (const auto& [i, j] :
         {std::pair{0, 0}, std::pair{width - 1, 0}, std::pair{0, height - 1},
          std::pair{width - 1, height - 1}, std::pair{960, 540}}) {
      CAPTURE(view.eye.x, i, j);
      const Vec3d expected = benchmark_direction(view, width, height, i, j);
      CHECK(length(camera_d.ray_through_pixel(i, j).direction - expected) <= 1e-15);
      CHECK(length(camera_f.ray_through_pixel(i, j).direction.as<double>() - expected) <= 1e-6);
      CHECK(camera_d.ray_through_pixel(i, j).tmin == 0.0);
      CHECK(camera_d.ray_through_pixel(i, j).tmax == std::numeric_limits<double>::infinity());
    }
    // Pixel (0, 0) is the top left corner: left of forward and above it.
    const RayD top_left = camera_d.ray_through_pixel(0, 0);
    CHECK(dot(top_left.direction, camera_d.basis.right) < 0);
    CHECK(dot(top_left.direction, camera_d.basis.up) > 0);
  }
}

TEST_CASE("pinhole: the CPU batch is the per-pixel function, row-major", "[ch03]") {
  const PinholeCamera<float> camera = camera_for<float>(k_views[0], 37, 19);
  const std::vector<RayF> rays = pinhole_rays_cpu(camera);
  REQUIRE(rays.size() == 37u * 19u);
  for (int j = 0; j < 19; ++j)
    for (int i = 0; i < 37; ++i) {
      const RayF expected = camera.ray_through_pixel(i, j);
      REQUIRE(rays[j * 37 + i].direction == expected.direction);
      REQUIRE(rays[j * 37 + i].origin == expected.origin);
    }
}

TEST_CASE("orthographic: rays are parallel and start on the view plane", "[ch03]") {
  const Vec3d eye{3, 2, 10}, target{0, 0, 0};
  const OrthographicCamera<double> camera =
      make_orthographic_camera(eye, target, Vec3d{0, 1, 0}, 4.0, 64, 48);
  const Vec3d forward = normalize(target - eye);
  CHECK(length(camera.basis.forward - forward) <= 1e-15);
  for (int j = 0; j < 48; ++j)
    for (int i = 0; i < 64; ++i) {
      const RayD ray = camera.ray_through_pixel(i, j);
      REQUIRE(ray.direction == camera.basis.forward);
      REQUIRE(std::abs(dot(ray.origin - eye, forward)) <= 1e-14);
    }
  // Neighbouring pixels are one pixel width (view height / image height) apart.
  const double pixel = 4.0 / 48;
  CHECK(length(camera.ray_through_pixel(1, 0).origin - camera.ray_through_pixel(0, 0).origin) ==
        Approx(pixel).epsilon(1e-12));
  CHECK(length(camera.ray_through_pixel(0, 1).origin - camera.ray_through_pixel(0, 0).origin) ==
        Approx(pixel).epsilon(1e-12));
  // The image spans the view height: the top row lies half a pixel below its top edge.
  CHECK(dot(camera.ray_through_pixel(0, 0).origin - eye, camera.basis.up) ==
        Approx(2.0 - pixel / 2).epsilon(1e-12));
}

namespace {

// Shadow rays leaving hit points on random spheres at `scale` (centre coordinates 0.5 to 1.5
// times the scale, radii 0.05 to 0.4 times it, eyes up to twice the scale away): each hit
// point comes from a float eye ray and the stable test, its shadow ray starts at
// origin_for(p, n) in a random direction on the normal's side. Counts shadow rays that hit
// their own sphere: a convex surface can never be hit again from just outside it.
template <class OriginFn>
long long count_self_hits(float scale, int count, unsigned seed, OriginFn origin_for) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), magnitude(0.5f, 1.5f),
      radius_fraction(0.05f, 0.4f), eye_distance(0.5f, 2.0f);
  const auto random_direction = [&] {
    for (;;) {
      const Vec3f v{unit(rng), unit(rng), unit(rng)};
      const float v_length = length(v);
      if (v_length > 0.1f && v_length <= 1.0f) return v / v_length;
    }
  };
  const auto random_coordinate = [&] {
    return std::copysign(magnitude(rng), unit(rng)) * scale;
  };
  long long self_hits = 0;
  for (int done = 0; done < count;) {
    const SphereF sphere{{random_coordinate(), random_coordinate(), random_coordinate()},
                         radius_fraction(rng) * scale};
    const Vec3f eye =
        sphere.centre + random_direction() * (sphere.radius + eye_distance(rng) * scale);
    const Vec3f target =
        sphere.centre + random_direction() * (0.99f * sphere.radius * std::abs(unit(rng)));
    const RayF eye_ray{eye, target - eye};
    const SphereHitF hit = intersect_sphere_stable(eye_ray, sphere);
    if (!hit.hit) continue;
    const Vec3f p = eye_ray.origin + eye_ray.direction * hit.t;
    const Vec3f n = normalize(p - sphere.centre);
    Vec3f shadow_direction = random_direction();
    if (dot(shadow_direction, n) < 0) shadow_direction = -shadow_direction;
    self_hits += intersect_sphere_stable(RayF{origin_for(p, n), shadow_direction}, sphere).hit;
    ++done;
  }
  return self_hits;
}

} // namespace

TEST_CASE("spawned rays never re-hit their own sphere, at scales 1 to 1e6", "[ch03]") {
  // Without the offset about half of them do; the offset needs 8 ulps here, and gives 128.
  for (const float scale : {1.0f, 10.0f, 1e2f, 1e3f, 1e4f, 1e5f, 1e6f}) {
    CAPTURE(scale);
    CHECK(count_self_hits(scale, 100'000, 17,
                          [](Vec3f p, Vec3f n) { return offset_ray_origin(p, n); }) == 0);
  }
}

TEST_CASE("a fixed offset of 1e-4 works at scale 1 and fails at scale 1e6", "[ch03]") {
  const auto fixed_offset = [](Vec3f p, Vec3f n) { return p + n * 1e-4f; };
  CHECK(count_self_hits(1.0f, 100'000, 23, fixed_offset) == 0);
  const long long self_hits = count_self_hits(1e6f, 100'000, 23, fixed_offset);
  std::printf(
      "fixed 1e-4 offset at scale 1e6: %lld of 100000 shadow rays hit their own sphere\n",
      self_hits);
  CHECK(self_hits > 10'000); // an ulp of 1e6 is 0.06: p + 1e-4 n rounds back to p
}
