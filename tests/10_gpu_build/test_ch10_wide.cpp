// Chapter 10 tests of the parallel collapse on CPU threads (the RT_HD passes the GPU runs too):
// the wide trees of LBVH and PLOC pass chapter 09's checker and give brute force's hits,
// closest and any; meshes of one to four triangles and of equal centroids collapse; leaves of
// more than three triangles are refused.
#include <vector>

#include "rt_catch.h"

#include "07_bvh/bvh_cases.h"
#include "build_cases.h"
#include "bvh_build.h"
#include "collapse.h"
#include "gpu_build.h"
#include "rt/error.h"
#include "wide_collapse.h"
#include "wide_traverse.h"

using namespace rt;
using namespace rt::ch10;
using namespace rt::ch10::testing;

namespace {

// Rays whose closest hit through the wide tree differs from brute force's in distance, and
// whose any-hit occlusion differs.
int wide_mismatches(const ch09::Wide4PackedBvh& tree, const Mesh& mesh,
                    const std::vector<RayF>& rays) {
  const ch04::MeshView view = ch04::host_view(mesh);
  int mismatches = 0;
  for (const RayF& ray : rays) {
    const ch04::MeshHit brute = ch04::closest_hit(ch04::TriangleVariant::watertight, view, ray);
    const ch09::TraceHit closest = ch09::trace_wide<ch09::Query::closest>(tree.view(), ray);
    const bool same_miss = brute.triangle < 0 && closest.triangle < 0;
    const bool same_t = brute.triangle >= 0 && closest.triangle >= 0 && brute.t == closest.t;
    if (!same_miss && !same_t) ++mismatches;
    const bool occluded = ch09::trace_wide<ch09::Query::any>(tree.view(), ray).triangle >= 0;
    if (occluded != (brute.triangle >= 0)) ++mismatches;
  }
  return mismatches;
}

} // namespace

TEST_CASE("the parallel collapse of LBVH and PLOC trees passes chapter 09's checker and "
          "finds brute force's hits",
          "[ch10]") {
  const std::vector<Mesh> meshes = {rt::testing::mixed_scene(6000, 51),
                                    rt::testing::random_soup(5000, 53, Vec3f{40.0f, 0, 0})};
  for (const Mesh& mesh : meshes) {
    const auto rays =
        rt::testing::random_rays(1500, 57, ch07::bounds_of(mesh.triangle(0)).lo, 60.0f);
    for (const int builder : {0, 1}) {
      CAPTURE(mesh.triangles.size(), builder);
      const ch07::Bvh binary = builder == 0
                                   ? build_lbvh(Backend::cpu, mesh, CodeWidth::bits30).bvh
                                   : build_ploc(Backend::cpu, mesh).bvh;
      const ch09::Wide4PackedBvh wide = collapse_to_wide4(Backend::cpu, binary);
      CHECK(ch09::check_wide_tree(wide, mesh).empty());
      CHECK(wide_mismatches(wide, mesh, rays) == 0);
      CHECK(wide.stats.nodes == static_cast<int>(wide.nodes.size()));
      CHECK(wide.stats.children_per_node > 3.0); // most nodes hold four children
      CHECK(wide.stats.triangles_per_leaf >= 1.0);
      CHECK(wide.stats.depth <= binary.stats.depth / 2 + 1);
    }
  }
}

TEST_CASE("the parallel collapse of small and degenerate meshes", "[ch10]") {
  std::vector<Mesh> meshes;
  for (int n = 1; n <= 4; ++n) meshes.push_back(rt::testing::random_soup(n, 61 + n));
  meshes.push_back(identical_triangles(100));
  meshes.push_back(power_of_two_chain(64));
  const auto rays = rt::testing::random_rays(500, 67, {0.0f, 0.0f, 0.0f}, 4.0f);
  for (const Mesh& mesh : meshes) {
    CAPTURE(mesh.triangles.size());
    const ch07::Bvh binary = build_lbvh(Backend::cpu, mesh, CodeWidth::bits30).bvh;
    const ch09::Wide4PackedBvh wide = collapse_to_wide4(Backend::cpu, binary);
    CHECK(ch09::check_wide_tree(wide, mesh).empty());
    CHECK(wide_mismatches(wide, mesh, rays) == 0);
    if (mesh.triangles.size() <= 4) CHECK(wide.nodes.size() == 1); // every triangle a leaf
  }
}

TEST_CASE("the parallel collapse takes chapter 07's leaves of up to three triangles",
          "[ch10]") {
  const Mesh mesh = rt::testing::mixed_scene(3000, 71);
  ch07::BuildOptions options;
  options.max_leaf_size = 3;
  const ch07::Bvh three = ch07::build_bvh(mesh, options);
  const ch09::Wide4PackedBvh wide = collapse_to_wide4(Backend::cpu, three);
  CHECK(ch09::check_wide_tree(wide, mesh).empty());
  options.max_leaf_size = 8; // eight equal triangles: one leaf of eight
  CHECK_THROWS_AS(
      collapse_to_wide4(Backend::cpu, ch07::build_bvh(identical_triangles(8), options)),
      InputError);
}
