// Chapter 10 tests of the moving scene on CPU threads: every time gives the same triangles with
// moved vertices; a tree built at one time and refitted to a later one passes chapter 07's
// checker and gives brute force's hits there; and the animation's figures and image come out
// for every frame and update; the frames made on the backend move the vertices as the host
// reference does, their binary and 4-wide trees pass the checkers, rebuilt or refitted, and the
// image through the 4-wide tree is the image through chapter 07's binary tree.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "07_bvh/bvh_cases.h"
#include "animation.h"
#include "build_cases.h"
#include "bvh_render.h"
#include "check_bvh.h"
#include "collapse.h"
#include "gpu_build.h"
#include "moving_frames.h"
#include "rt/error.h"
#include "shaded_render.h"
#include "shaded_scene.h"

using namespace rt;
using namespace rt::ch10;
using namespace rt::ch10::testing;

TEST_CASE("the moving scene keeps its triangles and moves its vertices", "[ch10]") {
  const ch05::ObjMesh start = moving_scene_at(0.0, 40);
  const ch05::ObjMesh later = moving_scene_at(0.7, 40);
  // The torus, four icospheres of 1 280 triangles, the floor's 6 faces of 4 x 4 cells.
  CHECK(start.geometry.triangles.size() == 40 * 40 + 4 * 1280 + 6 * 4 * 4 * 2);
  REQUIRE(later.geometry.triangles.size() == start.geometry.triangles.size());
  CHECK(std::memcmp(start.geometry.triangles.data(), later.geometry.triangles.data(),
                    start.geometry.triangles.size() * sizeof(ch04::IndexedTriangle)) == 0);
  CHECK(start.material_ids == later.material_ids);
  int moved = 0;
  for (std::size_t v = 0; v < start.geometry.vertices.size(); ++v)
    moved += !rt::testing::same_bits(start.geometry.vertices[v], later.geometry.vertices[v]);
  CHECK(moved > 3000); // of the torus's 800 and the spheres' 4 x 642; the floor stays
  CHECK(moving_scene_triangles(40) == static_cast<long long>(start.geometry.triangles.size()));
  CHECK(moving_scene_triangles(41) ==
        static_cast<long long>(moving_scene_at(0.0, 41).geometry.triangles.size()));
  CHECK_THROWS_AS(moving_scene_at(0.0, 7), InputError);
  // Beyond the 10 million triangles of chapter 05's models: refused before anything is made.
  CHECK_THROWS_WITH(moving_scene_at(0.0, k_max_moving_detail + 1),
                    Catch::Matchers::Contains("8 to 3161"));
}

TEST_CASE("a tree refitted to a later frame passes the checker and finds brute force's hits",
          "[ch10]") {
  const ch04::Mesh start = moving_scene_at(0.0, 60).geometry;
  const ch04::Mesh later = moving_scene_at(1.5, 60).geometry;
  const auto rays = rt::testing::random_rays(2000, 37, {0.0f, 0.0f, 0.0f}, 8.0f);
  for (const Builder builder : {Builder::lbvh, Builder::ploc, Builder::cpu_sah}) {
    CAPTURE(to_string(builder));
    ch07::Bvh tree = build_tree(builder, Backend::cpu, start).bvh;
    refit_bvh(Backend::cpu, tree, later);
    CHECK(ch07::check_bvh(tree, later).empty());
    CHECK(brute_force_mismatches(tree.view(), later, rays) == 0);
  }
}

TEST_CASE("the animation gives figures for every frame and update, and its last frame",
          "[ch10]") {
  AnimationOptions options;
  options.frames = 3;
  options.detail = 16;
  options.extent = {24, 16};
  const AnimationResult result = run_animation(options);
  REQUIRE(result.frames.size() == 2);
  for (const std::vector<FrameFigures>& update : result.frames) {
    REQUIRE(update.size() == 3);
    for (const FrameFigures& f : update) CHECK(f.sah_cost > 1.0);
  }
  // The first frame builds for both updates: the same tree, the same cost.
  CHECK(result.frames[0][0].sah_cost == result.frames[1][0].sah_cost);
  CHECK(result.last_frame.width == 24);
  CHECK(result.last_frame.pixels.size() == 24 * 16);
  const std::string csv = animation_csv(options, result);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 4);
  CHECK_THROWS_AS(parse_update("sometimes"), UsageError);
}

TEST_CASE("frames made on the backend: the vertices of the reference, trees that pass the "
          "checkers, the binary tree's image",
          "[ch10]") {
  const int detail = 40;
  const Extent extent{64, 36};
  const ch03::Camera<float> camera = ch03::make_camera<float>(moving_scene_camera(), extent);
  for (const Update update : {Update::rebuild, Update::refit}) {
    CAPTURE(to_string(update));
    MovingFrames frames(Backend::cpu, Builder::lbvh, detail);
    std::vector<Rgba8> pixels(extent.pixel_count());
    for (const double time : {0.0, 0.8, 1.7}) {
      CAPTURE(time);
      frames.frame(time, update, camera, extent, pixels.data());
      ch05::ObjMesh reference = moving_scene_at(time, detail);
      const std::vector<Vec3f> moved = frames.vertices();
      REQUIRE(moved.size() == reference.geometry.vertices.size());
      float worst = 0.0f;
      for (std::size_t v = 0; v < moved.size(); ++v)
        worst = std::max(worst, length(moved[v] - reference.geometry.vertices[v]));
      CHECK(worst < 2e-5f); // float against the reference's double: rounding only

      reference.geometry.vertices = moved; // the mesh as traced
      const ch07::Bvh binary = frames.binary_tree();
      CHECK(ch07::check_bvh(binary, reference.geometry).empty());
      CHECK(ch09::check_wide_tree(frames.wide_tree(), reference.geometry).empty());

      // Lights placed for the first frame, as the frames keep them; the vertices moved.
      ch06::ShadedScene scene = ch06::scene_from_obj(moving_scene_at(0.0, detail), {});
      scene.mesh.vertices = moved;
      const unsigned features = ch06::features_used(scene, false, true); // as the frames
      std::vector<Rgba8> through_binary(extent.pixel_count());
      ch07::render_bvh_shaded(Backend::cpu, features,
                              ch07::with_bvh(ch06::host_view(scene, features), binary.view()),
                              camera, extent, through_binary.data());
      int differing = 0;
      for (std::size_t p = 0; p < pixels.size(); ++p)
        differing += !rt::testing::same_bits(pixels[p], through_binary[p]);
      CHECK(differing <= 2); // exact ties between triangles may go either way
    }
  }
}

TEST_CASE("a model of the reader's waves in the torus's place: fitted, moved on the backend "
          "as the reference moves it, its trees pass the checkers",
          "[ch10]") {
  const ch04::Mesh fitted =
      fit_moving_model(ch04::make_icosphere(2, {100.0, 50.0, -20.0}, 30.0));
  Vec3f lo = fitted.vertices[0], hi = fitted.vertices[0];
  for (const Vec3f& v : fitted.vertices) {
    lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
    hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
  }
  CHECK(std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) == Approx(5.0f).epsilon(1e-5));
  CHECK(0.5f * (lo.x + hi.x) == Approx(0.0f).margin(1e-5));
  CHECK(0.5f * (lo.z + hi.z) == Approx(0.0f).margin(1e-5));
  CHECK(lo.y - k_wave_height > -1.6f); // the wave's lowest point stays above the floor

  const ch04::Mesh* model = &fitted;
  MovingFrames frames(Backend::cpu, Builder::lbvh, 40, model);
  const Extent extent{48, 27};
  const ch03::Camera<float> camera = ch03::make_camera<float>(moving_scene_camera(), extent);
  std::vector<Rgba8> pixels(extent.pixel_count());
  for (const Update update : {Update::rebuild, Update::refit})
    for (const double time : {0.0, 1.3}) {
      CAPTURE(to_string(update), time);
      frames.frame(time, update, camera, extent, pixels.data());
      ch05::ObjMesh reference = moving_scene_at(time, 40, model);
      const std::vector<Vec3f> moved = frames.vertices();
      REQUIRE(moved.size() == reference.geometry.vertices.size());
      float worst = 0.0f;
      for (std::size_t v = 0; v < moved.size(); ++v)
        worst = std::max(worst, length(moved[v] - reference.geometry.vertices[v]));
      CHECK(worst < 2e-5f);
      reference.geometry.vertices = moved;
      CHECK(ch07::check_bvh(frames.binary_tree(), reference.geometry).empty());
      CHECK(ch09::check_wide_tree(frames.wide_tree(), reference.geometry).empty());
    }
  CHECK_THROWS_AS(fit_moving_model(ch04::Mesh{}), InputError);
}
