// Chapter 10 tests of the parallel collapse on CPU threads (the RT_HD passes the GPU runs too):
// the wide trees of LBVH and PLOC pass chapter 09's checker and give brute force's hits,
// closest and any; meshes of one to four triangles and of equal centroids collapse; leaves of
// more than three triangles are refused; the sah rule makes chapter 09's SAH collapse's tree,
// node for node, and never costs more than the depth rule.
#include <bit>
#include <cstring>
#include <utility>
#include <vector>

#include "rt_catch.h"

#include "07_bvh/bvh_cases.h"
#include "build_cases.h"
#include "builders.h"
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

// Whether node x of `a` and node y of `b` head the same tree, however the two layouts number
// their nodes and records: the same boxes, child kinds and slots, leaf triangles (their
// records, bit for bit) and interior children, recursively. Counts the nodes compared.
bool same_subtree(const ch09::Wide4PackedBvh& a, int x, const ch09::Wide4PackedBvh& b, int y,
                  int& compared) {
  ++compared;
  const ch09::WideNode<4>& p = a.nodes[x];
  const ch09::WideNode<4>& q = b.nodes[y];
  for (int c = 0; c < 4; ++c) {
    const float pa[6] = {p.lo_x[c], p.lo_y[c], p.lo_z[c], p.hi_x[c], p.hi_y[c], p.hi_z[c]};
    const float qa[6] = {q.lo_x[c], q.lo_y[c], q.lo_z[c], q.hi_x[c], q.hi_y[c], q.hi_z[c]};
    if (std::memcmp(pa, qa, sizeof pa) != 0 || p.meta[c] != q.meta[c]) return false;
  }
  if (p.imask != q.imask) return false;
  const int k = ch09::PackedTriangles::k_records;
  int interior = 0;
  for (int c = 0; c < 4 && p.meta[c] != 0; ++c) {
    if (ch09::is_interior_meta(p.meta[c])) {
      if (!same_subtree(a, p.child_base + interior, b, q.child_base + interior, compared))
        return false;
      ++interior;
      continue;
    }
    const int offset = p.meta[c] & 31, count = std::popcount(unsigned(p.meta[c]) >> 5);
    const auto ra = a.triangles.begin() + std::ptrdiff_t(k) * (p.triangle_base + offset);
    const auto rb = b.triangles.begin() + std::ptrdiff_t(k) * (q.triangle_base + offset);
    if (std::memcmp(&*ra, &*rb, sizeof(float2) * k * count) != 0) return false;
  }
  return true;
}

} // namespace

TEST_CASE("the parallel collapse's sah rule makes chapter 09's SAH collapse's tree, node for "
          "node",
          "[ch10][wide-sah]") {
  const std::vector<std::pair<const char*, Mesh>> meshes = {
      {"mixed scene", rt::testing::mixed_scene(6000, 81)},
      {"soup at 1e5", rt::testing::random_soup(4000, 83, Vec3f{1e5f, 0, 0})},
      {"huge coordinates", huge_soup()},
      {"identical", identical_triangles(500)},
      {"power-of-two chain", power_of_two_chain(64)},
      {"one triangle", rt::testing::single_triangle()},
      {"two triangles", rt::testing::random_soup(2, 85)},
      {"five triangles", rt::testing::random_soup(5, 87)}};
  for (const auto& [name, mesh] : meshes) {
    for (const Builder builder : {Builder::cpu_sah, Builder::lbvh, Builder::hploc}) {
      CAPTURE(name, to_string(builder));
      const ch07::Bvh binary = build_tree(builder, Backend::cpu, mesh).bvh;
      const ch09::Wide4PackedBvh parallel =
          collapse_to_wide4(Backend::cpu, binary, CollapseRule::sah);
      const ch09::Wide4PackedBvh serial = ch09::pack_wide<4, ch09::PackedTriangles>(
          ch09::collapse(binary, 4, ch09::Collapse::sah));
      REQUIRE(parallel.nodes.size() == serial.nodes.size());
      CHECK(ch09::check_wide_tree(parallel, mesh).empty());
      int compared = 0;
      CHECK(same_subtree(parallel, 0, serial, 0, compared));
      CHECK(compared == static_cast<int>(serial.nodes.size()));
    }
  }
}

TEST_CASE("the sah rule's trees cost no more than the depth rule's, and trace the same hits",
          "[ch10][wide-sah]") {
  const Mesh mesh = rt::testing::mixed_scene(8000, 89);
  const auto rays =
      rt::testing::random_rays(1500, 91, ch07::bounds_of(mesh.triangle(0)).lo, 60.0f);
  for (const Builder builder : {Builder::lbvh, Builder::ploc, Builder::hploc}) {
    CAPTURE(to_string(builder));
    const ch07::Bvh binary = build_tree(builder, Backend::cpu, mesh).bvh;
    const ch09::Wide4PackedBvh sah = collapse_to_wide4(Backend::cpu, binary, CollapseRule::sah);
    const ch09::Wide4PackedBvh depth =
        collapse_to_wide4(Backend::cpu, binary, CollapseRule::depth);
    CHECK(wide_mismatches(sah, mesh, rays) == 0);
    // The depth rule's tree is one of those the sah rule chooses among (children made of
    // binary nodes below, leaves of at most three): the least cost is at most its cost.
    CHECK(sah.stats.sah_cost <= depth.stats.sah_cost * (1.0 + 1e-12));
    CHECK(sah.stats.sah_cost < depth.stats.sah_cost * 0.99); // and here clearly less
  }
}

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
