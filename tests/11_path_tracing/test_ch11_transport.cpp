// Chapter 11 tests of light transport against what is known exactly: the white furnace
// (radiance Le / (1 - a) inside a closed emitting sphere, whatever the strategy), a disc and a
// sphere lighting a floor (E = pi Le sin^2 theta, pi Le (R / d)^2), a sun and a sky on a floor;
// and the pieces the estimators are made of: the random numbers, the power heuristic, the light
// table. The samplers' densities are tested in test_ch11_sampling.cpp.
#include <cmath>
#include <set>

#include "rt_catch.h"

#include "path_cases.h"

using namespace rt;
using namespace rt::ch11;
using namespace rt::ch11::testing;

TEST_CASE("white furnace: Le / (1 - a) within 3 standard errors, every strategy", "[ch11]") {
  const Extent extent{24, 16};
  for (const float albedo : {0.5f, 0.8f}) {
    const PathScene furnace = make_furnace(2, albedo, 1.0f);
    const double expected = 1.0 / (1.0 - albedo);
    for (const Strategy strategy : {Strategy::mis, Strategy::light, Strategy::bsdf}) {
      CAPTURE(albedo, to_string(strategy));
      unsigned long long non_finite = 1;
      const MeanAndError stats = pixel_statistics(render_mean(
          furnace, Backend::cpu, furnace_camera(), extent, 32,
          {PathVariant::megakernel, KernelKind::specialised, strategy}, &non_finite));
      CAPTURE(stats.mean, stats.standard_error, expected);
      CHECK(non_finite == 0);
      CHECK(stats.standard_error > 0.0); // Russian roulette makes every pixel differ
      CHECK(std::abs(stats.mean - expected) < 3.0 * stats.standard_error);
    }
  }
}

TEST_CASE("a disc over a floor: albedo / pi * pi Le sin^2 theta right below it", "[ch11]") {
  const float radius = 0.5f, height = 1.0f, emission = 2.0f, albedo = 0.5f;
  const PathScene scene = make_disc_over_floor(radius, height, emission, albedo, 8.0f, 256);
  CameraSpec camera; // between disc and floor, looking straight down at a small patch
  camera.eye = {0.0, 0.5, 0.0};
  camera.target = {0.0, 0.0, 0.0};
  camera.up = {0.0, 0.0, -1.0};
  camera.fov_degrees = 2.0;
  const double sin2 = radius * radius / double(radius * radius + height * height);
  const double expected = albedo / k_pi * (k_pi * emission * sin2);
  for (const Strategy strategy : {Strategy::mis, Strategy::light, Strategy::bsdf}) {
    CAPTURE(to_string(strategy));
    const MeanAndError stats = pixel_statistics(
        render_mean(scene, Backend::cpu, camera, {16, 16}, 32,
                    {PathVariant::megakernel, KernelKind::specialised, strategy}));
    CAPTURE(stats.mean, stats.standard_error, expected);
    CHECK(std::abs(stats.mean - expected) < 3.0 * stats.standard_error);
    CHECK(stats.standard_error < 0.05 * expected); // and the test has the power to notice
  }
}

TEST_CASE("a sphere over a floor: albedo / pi * pi Le (R / d)^2 right below it", "[ch11]") {
  const float radius = 0.5f, distance = 2.0f, emission = 3.0f, albedo = 0.7f;
  PathScene scene = make_disc_over_floor(radius, 1.0f, 0.0f, albedo, 40.0f, 8);
  scene.mesh.triangles.resize(2); // the floor alone, then an emitting icosphere over it
  scene.material.resize(2);
  ch04::append_mesh(scene.mesh, ch04::make_icosphere(4, {0.0, distance, 0.0}, radius));
  scene.materials[1].emission = {emission, emission, emission};
  scene.material.resize(scene.mesh.triangles.size(), 1);
  scene.lights = build_light_table(scene);
  CameraSpec camera;
  camera.eye = {0.0, 0.5, 0.0};
  camera.target = {0.0, 0.0, 0.0};
  camera.up = {0.0, 0.0, -1.0};
  camera.fov_degrees = 2.0;
  const double ratio = double(radius) / distance;
  const double expected = albedo / k_pi * (k_pi * emission * ratio * ratio);
  for (const Strategy strategy : {Strategy::mis, Strategy::light, Strategy::bsdf}) {
    CAPTURE(to_string(strategy));
    const MeanAndError stats = pixel_statistics(
        render_mean(scene, Backend::cpu, camera, {16, 16}, 32,
                    {PathVariant::megakernel, KernelKind::specialised, strategy}));
    CAPTURE(stats.mean, stats.standard_error, expected);
    CHECK(std::abs(stats.mean - expected) < 3.0 * stats.standard_error);
    CHECK(stats.standard_error < 0.1 * expected);
  }
}

namespace {

// A floor of albedo 0.6 under a sun (irradiance 2, 45 degrees up) and a sky of 0.25, nothing
// else: every pixel's exact value is albedo / pi * E cos + albedo * sky.
PathScene sun_and_sky_floor() {
  PathScene scene = make_disc_over_floor(0.5f, 1.0f, 0.0f, 0.6f, 100.0f, 8);
  scene.mesh.triangles.resize(2); // the floor alone
  scene.material.resize(2);
  scene.lights = build_light_table(scene);
  scene.environment.sun_direction = normalize(Vec3f{0.0f, 1.0f, 1.0f});
  scene.environment.sun_irradiance = {2.0f, 2.0f, 2.0f};
  scene.environment.sky = {0.25f, 0.25f, 0.25f};
  return scene;
}

// A narrow view straight down at the middle of that floor.
CameraSpec looking_down_at_floor() {
  CameraSpec camera;
  camera.eye = {3.0, 0.4, 0.0};
  camera.target = {3.0, 0.0, 0.0};
  camera.up = {0.0, 0.0, -1.0};
  camera.fov_degrees = 5.0;
  return camera;
}

} // namespace

TEST_CASE("a sun and a sky over a floor: albedo / pi * E cos and albedo * sky", "[ch11]") {
  PathScene scene = sun_and_sky_floor();
  const CameraSpec camera = looking_down_at_floor();
  REQUIRE(features_used(scene) == (k_sky | k_sun));
  // Every bounce from the floor reaches the sky, so each sample is exact.
  const double expected = 0.6 / k_pi * 2.0 * std::sqrt(0.5) + 0.6 * 0.25;
  for (const Vec3f& p : render_mean(scene, Backend::cpu, camera, {8, 8}, 4)) {
    CHECK(p.x == Approx(expected).epsilon(1e-5));
    CHECK(p.y == Approx(expected).epsilon(1e-5));
  }
}

TEST_CASE("sample numbers: from 0 up to 1, different for each coordinate", "[ch11]") {
  std::set<float> seen;
  for (unsigned pixel = 0; pixel < 4; ++pixel)
    for (unsigned sample = 0; sample < 4; ++sample)
      for (unsigned vertex = 0; vertex < 4; ++vertex)
        for (unsigned dimension = 0; dimension < k_dimensions; ++dimension) {
          const float u = sample_number(pixel, sample, vertex, dimension);
          CHECK(u >= 0.0f);
          CHECK(u < 1.0f);
          seen.insert(u);
        }
  CHECK(seen.size() > 500); // of 512: a collision or two of 24-bit values is chance
  double sum = 0.0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) sum += sample_number(unsigned(i), 7u, 2u, k_bsdf_u);
  CHECK(sum / n == Approx(0.5).margin(0.005));
}

TEST_CASE("power heuristic: the two strategies' weights add to one", "[ch11]") {
  for (const float a : {0.0f, 0.1f, 1.0f, 37.0f})
    for (const float b : {0.1f, 1.0f, 1e4f})
      CHECK(power_heuristic(a, b) + power_heuristic(b, a) == Approx(1.0f).epsilon(1e-6));
  CHECK(power_heuristic(0.0f, 0.0f) == 0.0f);
}

TEST_CASE("light table: emitters picked by area times luminance", "[ch11]") {
  PathScene scene;
  scene.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {0, 2, 0}};
  scene.mesh.triangles = {{0, 1, 2}, {0, 3, 4}, {0, 1, 2}};
  scene.materials = {{{0.5f, 0.5f, 0.5f}, {1, 1, 1}}, {{0.5f, 0.5f, 0.5f}, {0, 0, 0}}};
  scene.material = {0, 0, 1};
  const LightTable table = build_light_table(scene);
  REQUIRE(table.triangles == std::vector<int>{0, 1});
  CHECK(table.power == Approx(0.5 + 2.0));
  CHECK(table.cdf[0] == Approx(0.2f));
  CHECK(table.cdf[1] == 1.0f);

  scene.materials[0].emission = {1, -1, 1};
  CHECK_THROWS_AS(build_light_table(scene), InputError);
  scene.materials[0].emission = {1, 1, 1};
  scene.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}}; // flat
  CHECK_THROWS_AS(build_light_table(scene), InputError);
}

TEST_CASE("the Cornell room's MTL: Kd as albedo, Ke as emission", "[ch11]") {
  long long defaulted = -1;
  const PathScene room = load_path_scene(k_room, &defaulted);
  CHECK(defaulted == 0);
  CHECK(room.lights.triangles.size() == 2); // the light quad
  CHECK(room.lights.power == Approx(0.5 * 0.4 * luminance({17, 12, 4})).epsilon(1e-5));
  bool red = false;
  for (const PathMaterial& m : room.materials)
    red = red || (m.albedo.x == 0.65f && m.albedo.y == 0.05f);
  CHECK(red);
}

// ---- the same answers with every sampler (samplers.h)
// ----------------------------------------- Each sampler's numbers are uniform, so every
// estimator stays unbiased; the pixels' means stay independent of one another except zsobol's,
// whose neighbours offset each other's error: the standard error computed as if they were
// independent is then too large, which only makes the test more lenient for it.

namespace {

RenderSettings with_sampler(SamplerKind sampler, int samples,
                            Strategy strategy = Strategy::mis) {
  RenderSettings settings{PathVariant::megakernel, KernelKind::specialised, strategy};
  settings.sampler = sampler;
  settings.sampler_samples = samples;
  return settings;
}

} // namespace

TEST_CASE("white furnace with every sampler: Le / (1 - a) within 3 standard errors",
          "[ch11][samplers]") {
  const Extent extent{24, 16};
  const int samples = 32;
  for (const float albedo : {0.5f, 0.8f}) {
    const PathScene furnace = make_furnace(2, albedo, 1.0f);
    const double expected = 1.0 / (1.0 - albedo);
    for (const SamplerKind sampler : k_samplers) {
      CAPTURE(albedo, to_string(sampler));
      unsigned long long non_finite = 1;
      const MeanAndError stats =
          pixel_statistics(render_mean(furnace, Backend::cpu, furnace_camera(), extent, samples,
                                       with_sampler(sampler, samples), &non_finite));
      CAPTURE(stats.mean, stats.standard_error, expected);
      CHECK(non_finite == 0);
      CHECK(stats.standard_error > 0.0);
      CHECK(std::abs(stats.mean - expected) < 3.0 * stats.standard_error);
    }
  }
}

TEST_CASE("a disc and a sphere over a floor with every sampler: the exact irradiance within 3 "
          "standard errors",
          "[ch11][samplers]") {
  const int samples = 32;
  CameraSpec camera; // between the lamp and the floor, looking straight down at a small patch
  camera.eye = {0.0, 0.5, 0.0};
  camera.target = {0.0, 0.0, 0.0};
  camera.up = {0.0, 0.0, -1.0};
  camera.fov_degrees = 2.0;
  // The disc: albedo / pi * pi Le sin^2 theta.
  const float radius = 0.5f, height = 1.0f, emission = 2.0f, albedo = 0.5f;
  const PathScene disc = make_disc_over_floor(radius, height, emission, albedo, 8.0f, 256);
  const double sin2 = radius * radius / double(radius * radius + height * height);
  const double disc_expected = albedo / k_pi * (k_pi * emission * sin2);
  // The sphere: albedo / pi * pi Le (R / d)^2.
  const float distance = 2.0f, sphere_emission = 3.0f, floor_albedo = 0.7f;
  PathScene sphere = make_disc_over_floor(radius, 1.0f, 0.0f, floor_albedo, 40.0f, 8);
  sphere.mesh.triangles.resize(2);
  sphere.material.resize(2);
  ch04::append_mesh(sphere.mesh, ch04::make_icosphere(4, {0.0, distance, 0.0}, radius));
  sphere.materials[1].emission = {sphere_emission, sphere_emission, sphere_emission};
  sphere.material.resize(sphere.mesh.triangles.size(), 1);
  sphere.lights = build_light_table(sphere);
  const double ratio = double(radius) / distance;
  const double sphere_expected = floor_albedo / k_pi * (k_pi * sphere_emission * ratio * ratio);
  for (const SamplerKind sampler : k_samplers)
    for (const Strategy strategy : {Strategy::mis, Strategy::light, Strategy::bsdf}) {
      CAPTURE(to_string(sampler), to_string(strategy));
      const RenderSettings settings = with_sampler(sampler, samples, strategy);
      const MeanAndError lit_by_disc = pixel_statistics(
          render_mean(disc, Backend::cpu, camera, {16, 16}, samples, settings));
      CAPTURE(lit_by_disc.mean, lit_by_disc.standard_error, disc_expected);
      CHECK(std::abs(lit_by_disc.mean - disc_expected) < 3.0 * lit_by_disc.standard_error);
      CHECK(lit_by_disc.standard_error < 0.05 * disc_expected);
      const MeanAndError lit_by_sphere = pixel_statistics(
          render_mean(sphere, Backend::cpu, camera, {16, 16}, samples, settings));
      CAPTURE(lit_by_sphere.mean, lit_by_sphere.standard_error, sphere_expected);
      CHECK(std::abs(lit_by_sphere.mean - sphere_expected) <
            3.0 * lit_by_sphere.standard_error);
      CHECK(lit_by_sphere.standard_error < 0.1 * sphere_expected);
    }
}

TEST_CASE("a sun and a sky over a floor with every sampler: every sample exact",
          "[ch11][samplers]") {
  PathScene scene = sun_and_sky_floor();
  const CameraSpec camera = looking_down_at_floor();
  const double expected = 0.6 / k_pi * 2.0 * std::sqrt(0.5) + 0.6 * 0.25;
  for (const SamplerKind sampler : k_samplers) {
    CAPTURE(to_string(sampler));
    int wrong = 0;
    for (const Vec3f& p :
         render_mean(scene, Backend::cpu, camera, {8, 8}, 4, with_sampler(sampler, 4)))
      wrong += !(std::abs(p.x - expected) <= 1e-5 * expected &&
                 std::abs(p.y - expected) <= 1e-5 * expected);
    CHECK(wrong == 0);
  }
}
