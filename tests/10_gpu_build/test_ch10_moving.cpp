// Chapter 10 tests of the moving scene on CPU threads: every time gives the same triangles with
// moved vertices; a tree built at one time and refitted to a later one passes chapter 07's
// checker and gives brute force's hits there; and the animation's figures and image come out
// for every frame and update.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "07_bvh/bvh_cases.h"
#include "animation.h"
#include "build_cases.h"
#include "check_bvh.h"
#include "gpu_build.h"
#include "rt/error.h"

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
  CHECK_THROWS_AS(moving_scene_at(0.0, 7), InputError);
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
