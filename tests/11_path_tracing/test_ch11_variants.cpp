// Chapter 11 tests that different code gives the same image: the specialised kernel and the
// all-features kernel, the megakernel and the wavefront stages, one run and the next, a moved
// scene and a renderer made for it; and that the Cornell room renders alike at every scale,
// without NaN.
#include <cmath>

#include "rt_catch.h"

#include "animation.h"
#include "collapse.h"
#include "path_cases.h"
#include "rt/error.h"

using namespace rt;
using namespace rt::ch11;
using namespace rt::ch11::testing;

namespace {

const Extent k_small{40, 30};

PathScene room_with_sky_and_sun() { // every feature on: the all-features kernel's case too
  PathScene room = load_path_scene(k_room);
  room.environment.sky = {0.2f, 0.3f, 0.4f};
  room.environment.sun_direction = normalize(Vec3f{0.3f, 1.0f, 0.5f});
  room.environment.sun_irradiance = {1.0f, 1.0f, 1.0f};
  return room;
}

} // namespace

TEST_CASE("specialised and all-features kernels give the same sums", "[ch11]") {
  const PathScene room = load_path_scene(k_room);
  REQUIRE(features_used(room) == k_emitters);
  for (const Strategy strategy : {Strategy::mis, Strategy::bsdf}) {
    const auto specialised =
        render_sums(room, Backend::cpu, cornell_camera(), k_small, 4,
                    {PathVariant::megakernel, KernelKind::specialised, strategy});
    const auto all = render_sums(room, Backend::cpu, cornell_camera(), k_small, 4,
                                 {PathVariant::megakernel, KernelKind::all_features, strategy});
    CHECK(same_sums(specialised, all));
  }
  // An open scene lit by the sky and the sun alone, a dark disc's shadow on a floor: another
  // specialised kernel.
  PathScene open = make_disc_over_floor(0.5f, 1.0f, 0.0f, 0.6f, 8.0f, 16);
  open.environment = room_with_sky_and_sun().environment;
  REQUIRE(features_used(open) == (k_sky | k_sun));
  CameraSpec camera;
  camera.eye = {0.0, 3.0, 4.0};
  camera.target = {0.0, 0.0, 0.0};
  const auto specialised = render_sums(open, Backend::cpu, camera, k_small, 4);
  const auto all = render_sums(open, Backend::cpu, camera, k_small, 4,
                               {PathVariant::megakernel, KernelKind::all_features});
  CHECK(same_sums(specialised, all));
  CHECK(specialised[k_small.width * k_small.height / 2].x > 0.0f); // lit, not black
}

TEST_CASE("megakernel and wavefront give the same sums, every feature on", "[ch11]") {
  const PathScene room = room_with_sky_and_sun();
  REQUIRE(features_used(room) == k_all_path_features);
  for (const KernelKind kernel : {KernelKind::specialised, KernelKind::all_features}) {
    const auto mega = render_sums(room, Backend::cpu, cornell_camera(), k_small, 3,
                                  {PathVariant::megakernel, kernel, Strategy::mis});
    const auto wave = render_sums(room, Backend::cpu, cornell_camera(), k_small, 3,
                                  {PathVariant::wavefront, kernel, Strategy::mis});
    CHECK(same_sums(mega, wave));
  }
}

TEST_CASE("the CPU renders the same sums twice, and progressively as at once", "[ch11]") {
  const PathScene room = load_path_scene(k_room);
  const auto first = render_sums(room, Backend::cpu, cornell_camera(), k_small, 4);
  CHECK(same_sums(first, render_sums(room, Backend::cpu, cornell_camera(), k_small, 4)));
  PathRenderer renderer(room, Backend::cpu);
  renderer.restart(cornell_camera(), k_small);
  for (int i = 0; i < 4; ++i) renderer.add_samples({}, 1);
  CHECK(same_sums(first, renderer.sums()));
  CHECK(renderer.non_finite() == 0);
}

TEST_CASE("the Cornell room from scale 1 to 1e6: the same image, no NaN", "[ch11]") {
  const Extent extent{32, 24};
  const int samples = 16;
  const PathScene room = load_path_scene(k_room);
  const std::vector<Vec3f> unit =
      render_mean(room, Backend::cpu, cornell_camera(), extent, samples);
  double unit_mean = 0.0;
  for (const Vec3f& p : unit) unit_mean += (p.x + p.y + p.z) / 3.0 / double(unit.size());
  for (const double scale : {1e-3, 1e3, 1e6}) {
    CAPTURE(scale);
    PathScene scaled = room;
    scale_scene(scaled, scale);
    unsigned long long non_finite = 1;
    const std::vector<Vec3f> image =
        render_mean(scaled, Backend::cpu, scaled_camera(cornell_camera(), scale), extent,
                    samples, {}, &non_finite);
    CHECK(non_finite == 0);
    // The same random numbers follow nearly the same paths: a self-hit would end a path
    // early (darker) and an escape through a wall would lose it (darker still).
    double difference = 0.0, mean = 0.0;
    for (std::size_t i = 0; i < image.size(); ++i) {
      const Vec3f d = image[i] - unit[i];
      difference += (std::abs(d.x) + std::abs(d.y) + std::abs(d.z)) / 3.0 / double(unit.size());
      mean += (image[i].x + image[i].y + image[i].z) / 3.0 / double(unit.size());
    }
    CHECK(mean == Approx(unit_mean).epsilon(0.01));
    CHECK(difference < 0.02 * unit_mean);
  }
}

TEST_CASE("rays spawned from every triangle of the room never hit it again, at any scale",
          "[ch11]") {
  for (const double scale : {1.0, 1e-3, 1e3, 1e6}) {
    CAPTURE(scale);
    PathScene room = load_path_scene(k_room);
    scale_scene(room, scale);
    const PathTree tree = build_path_tree(room.mesh);
    long long self_hits = 0, rays = 0;
    for (int i = 0; i < static_cast<int>(room.mesh.triangles.size()); ++i) {
      const ch04::TriangleF t = room.mesh.triangle(i);
      for (unsigned k = 0; k < 64; ++k) {
        const Vec3f p = point_on_triangle(t.v0, t.v1, t.v2, sample_number(i, k, 1, 0),
                                          sample_number(i, k, 1, 1));
        for (const float side : {1.0f, -1.0f}) { // both faces reflect
          const Vec3f n = front_normal(t, {0, 1, 0}) * side;
          const Vec3f d =
              sample_cosine(n, sample_number(i, k, 1, 2), sample_number(i, k, 1, 3)).direction;
          const ch07::TraceHit hit =
              ch09::trace_wide<Query::closest>(tree.view(), {spawn_origin(p, n, t), d});
          self_hits += hit.triangle == i ? 1 : 0;
          ++rays;
        }
      }
    }
    CHECK(rays == 218 * 64 * 2);
    CHECK(self_hits == 0);
  }
}

TEST_CASE("the report's ray count: what one sample traces, and nothing changed by counting",
          "[ch11]") {
  const PathScene room = load_path_scene(k_room);
  const long long pixels = k_small.pixel_count();
  PathRenderer renderer(room, Backend::cpu);
  renderer.restart(cornell_camera(), k_small);
  const RayCounts mis = renderer.add_counted_sample(Strategy::mis);
  CHECK(same_sums(renderer.sums(), render_sums(room, Backend::cpu, cornell_camera(), k_small, 1,
                                               {PathVariant::wavefront})));
  CHECK(mis.extension > pixels);      // every camera ray, and the paths that bounce on
  CHECK(mis.shadow > 0);              // next-event estimation towards the light
  CHECK(mis.shadow <= mis.extension); // one light sample per vertex, the room has no sun
  renderer.restart(cornell_camera(), k_small);
  const RayCounts bsdf = renderer.add_counted_sample(Strategy::bsdf);
  CHECK(bsdf.shadow == 0); // bounces alone: no shadow rays
  CHECK(bsdf.extension > pixels);
  // Looking away from everything under a sky: each path is its camera ray, nothing more.
  PathScene open = make_disc_over_floor(0.5f, 1.0f, 0.0f, 0.6f, 8.0f, 16);
  open.environment.sky = {0.5f, 0.5f, 0.5f};
  CameraSpec up;
  up.eye = {0.0, 3.0, 0.0};
  up.target = {0.0, 10.0, 0.1};
  PathRenderer sky(open, Backend::cpu);
  sky.restart(up, k_small);
  const RayCounts escaping = sky.add_counted_sample(Strategy::mis);
  CHECK(escaping.extension == pixels);
  CHECK(escaping.shadow == 0);
}

TEST_CASE("a moved scene renders as a renderer made for it: the tree built again, the sums "
          "started again",
          "[ch11]") {
  const PathScene start = lit_moving_scene(0.0, 24);
  const PathScene later = lit_moving_scene(0.9, 24);
  REQUIRE(later.mesh.triangles.size() == start.mesh.triangles.size());
  const RenderSettings settings{PathVariant::megakernel, KernelKind::specialised,
                                Strategy::mis};
  const CameraSpec camera = ch10::moving_scene_camera();
  PathRenderer moved(start, Backend::cpu, TreeBuild::lbvh);
  moved.restart(camera, k_small);
  moved.add_samples(settings, 2);
  moved.move_vertices(later.mesh.vertices);
  CHECK(moved.samples() == 0);
  moved.add_samples(settings, 3);
  PathRenderer fresh(later, Backend::cpu, TreeBuild::lbvh);
  fresh.restart(camera, k_small);
  fresh.add_samples(settings, 3);
  CHECK(same_sums(moved.sums(), fresh.sums()));
  CHECK(pixel_statistics(fresh.mean_radiance()).mean > 0.1); // lit: the sums can differ
  // The tree a moving scene can afford finds the same hits as the SAH tree: the same image up
  // to exact ties between triangles.
  PathRenderer sah(later, Backend::cpu, TreeBuild::sah);
  sah.restart(camera, k_small);
  sah.add_samples(settings, 3);
  const std::vector<float4> a = fresh.sums(), b = sah.sums();
  int differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    differing += a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z;
  CHECK(differing <= 2);
  std::vector<Vec3f> too_few = later.mesh.vertices;
  too_few.pop_back();
  CHECK_THROWS_AS(moved.move_vertices(too_few), InputError);
}

TEST_CASE("every sampler: megakernel, persistent threads and wavefront give the same sums, "
          "progressively as at once, and each sampler an image of its own",
          "[ch11][samplers]") {
  const Extent extent{16, 12};
  const int samples = 4;
  struct Case {
    const char* name;
    PathScene scene;
    CameraSpec camera;
  };
  const Case cases[] = {{"the Cornell room", load_path_scene(k_room), cornell_camera()},
                        {"the moving scene under the sky and sun", lit_moving_scene(0.0, 8),
                         ch10::moving_scene_camera()}};
  for (const Case& c : cases) {
    std::vector<float4> independent;
    for (const SamplerKind sampler : k_samplers) {
      CAPTURE(c.name, to_string(sampler));
      RenderSettings settings{PathVariant::megakernel, KernelKind::specialised, Strategy::mis};
      settings.sampler = sampler;
      settings.sampler_samples = samples;
      const auto mega = render_sums(c.scene, Backend::cpu, c.camera, extent, samples, settings);
      settings.variant = PathVariant::persistent;
      CHECK(same_sums(mega,
                      render_sums(c.scene, Backend::cpu, c.camera, extent, samples, settings)));
      settings.variant = PathVariant::wavefront;
      CHECK(same_sums(mega,
                      render_sums(c.scene, Backend::cpu, c.camera, extent, samples, settings)));
      // One sample at a time: the numbers depend on the sample's index, not on the pass.
      PathRenderer renderer(c.scene, Backend::cpu);
      renderer.restart(c.camera, extent);
      settings.variant = PathVariant::megakernel;
      for (int i = 0; i < samples; ++i) renderer.add_samples(settings, 1);
      CHECK(same_sums(mega, renderer.sums()));
      CHECK(renderer.non_finite() == 0);
      // The setting reaches the kernels: each sampler draws other paths than the hash.
      if (sampler == SamplerKind::independent) {
        independent = mega; // the hash, whatever the count: the default settings' image
        CHECK(same_sums(mega, render_sums(c.scene, Backend::cpu, c.camera, extent, samples)));
      } else {
        CHECK(!same_sums(mega, independent));
      }
    }
  }
}
