// Chapter 10 tests of the parallel builds on CPU threads (the RT_HD passes the GPU runs too):
// Morton codes against hand-computed ones; LBVH trees of both code widths pass chapter 07's
// checker and give brute force's hits; equal codes make a balanced tree; a chain of powers of
// two stays within the depth bound; PLOC's rounds stay few on centroids that tie or chain; the
// refit of a bent mesh passes the checker and gives brute force's hits; no ray leaks out of
// closed meshes, through a refitted tree too; bad input is refused.
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "rt_catch.h"

#include "07_bvh/bvh_cases.h"
#include "adversarial_rays.h"
#include "build_cases.h"
#include "bvh_build.h"
#include "check_bvh.h"
#include "gpu_build.h"
#include "karras.h"
#include "leak_configurations.h"
#include "morton.h"
#include "rt/error.h"

using namespace rt;
using namespace rt::ch10;
using namespace rt::ch10::testing;

namespace {

constexpr CodeWidth k_widths[] = {CodeWidth::bits30, CodeWidth::bits63};

std::vector<std::string> problems_of(const ch07::Bvh& bvh, const Mesh& mesh) {
  return ch07::check_bvh(bvh, mesh);
}

} // namespace

TEST_CASE("Morton codes interleave the bits as computed by hand", "[ch10]") {
  CHECK(spread_bits_10(0b1011u) == 0b1000001001u); // bits 0, 1, 3 to 0, 3, 9
  CHECK(morton30(1, 0, 0) == 0b100u);
  CHECK(morton30(0, 1, 0) == 0b010u);
  CHECK(morton30(0, 0, 1) == 0b001u);
  // x = 011, y = 101, z = 110: from bit 0 up, the triples (x y z) are 110, 101, 011.
  CHECK(morton30(3, 5, 6) == 0b011'101'110u);
  CHECK(morton63(3, 5, 6) == 0b011'101'110u);
  CHECK(morton30(1023, 1023, 1023) == (1u << 30) - 1);
  CHECK(morton63(1u << 20, 0, 0) == 1ull << 62);
  CHECK(morton63((1u << 21) - 1, (1u << 21) - 1, (1u << 21) - 1) == (1ull << 63) - 1);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 1000; ++trial) { // against the bit-by-bit definition
    const std::uint64_t x = rng() & 0x1fffff;
    std::uint64_t slow = 0;
    for (int k = 0; k < 21; ++k) slow |= ((x >> k) & 1) << (3 * k);
    CHECK(spread_bits_21(x) == slow);
    CHECK(spread_bits_10(static_cast<std::uint32_t>(x)) == (slow & 0x09249249u));
  }
}

TEST_CASE("grid cells cover the bounds, ends included, flat axes in cell 0", "[ch10]") {
  CHECK(grid_cell(0.0f, 0.0f, 1.0f, 10) == 0);
  CHECK(grid_cell(0.25f, 0.0f, 1.0f, 10) == 256);
  CHECK(grid_cell(0.5f, 0.0f, 1.0f, 10) == 512);
  CHECK(grid_cell(1.0f, 0.0f, 1.0f, 10) == 1023);
  CHECK(grid_cell(1.0f, 0.0f, 1.0f, 21) == (1u << 21) - 1);
  CHECK(grid_cell(3.0f, 3.0f, 3.0f, 10) == 0);
  const float big = std::numeric_limits<float>::max();
  CHECK(grid_cell(big, -big, big, 10) == 1023); // no overflow across the whole float range
  CHECK(grid_cell(0.0f, -big, big, 10) == 512);
}

TEST_CASE("Karras's node 0 is the root and covers every leaf", "[ch10]") {
  const std::uint32_t codes[] = {1, 2, 4, 5, 19, 24, 25, 30};
  const KarrasNode root = karras_node(codes, 8, 0);
  CHECK(root.first == 0);
  CHECK(root.last == 7);
  CHECK(root.child[0] == 3); // 0..3 below 16 (bit 4 clear), 4..7 above
  CHECK(!root.is_leaf[0]);
  // Equal codes: the index bits split them evenly.
  const std::uint32_t same[] = {7, 7, 7, 7, 7, 7, 7, 7};
  CHECK(karras_node(same, 8, 0).child[0] == 3);
  CHECK(delta(same, 8, 0, 1) == 32 + std::countl_zero(1u));
  CHECK(delta(same, 8, 0, 8) == -1);
}

TEST_CASE("LBVH trees pass chapter 07's checker and give brute force's hits", "[ch10]") {
  for (const CodeWidth width : k_widths) {
    for (const Vec3f centre : {Vec3f{}, Vec3f{1e5f, -1e5f, 5e4f}}) {
      CAPTURE(to_string(width), centre.x);
      const Mesh scene = rt::testing::mixed_scene(2000, 5);
      Mesh moved = scene;
      for (Vec3f& v : moved.vertices) v = v + centre;
      const GpuBuild build = build_lbvh(Backend::cpu, moved, width);
      CHECK(problems_of(build.bvh, moved).empty());
      CHECK(build.codes == width);
      CHECK(build.note.empty());
      CHECK(build.bvh.stats.leaves == static_cast<int>(moved.triangles.size()));
      const auto rays = rt::testing::random_rays(3000, 9, centre, 10.0f);
      CHECK(brute_force_mismatches(build.bvh.view(), moved, rays) == 0);
    }
  }
}

TEST_CASE("the CPU build is the same tree every time, whatever the threads do", "[ch10]") {
  const Mesh scene = rt::testing::random_soup(5000, 17);
  const GpuBuild a = build_lbvh(Backend::cpu, scene, CodeWidth::bits63);
  const GpuBuild b = build_lbvh(Backend::cpu, scene, CodeWidth::bits63);
  CHECK(rt::testing::same_bits(a.bvh.nodes, b.bvh.nodes));
  CHECK(a.bvh.triangle_ids == b.bvh.triangle_ids);
}

TEST_CASE("equal codes give a balanced tree through the index tie-break", "[ch10]") {
  for (const int n : {2, 3, 1000, 4096}) {
    CAPTURE(n);
    const Mesh mesh = identical_triangles(n);
    for (const CodeWidth width : k_widths) {
      const GpuBuild build = build_lbvh(Backend::cpu, mesh, width);
      CHECK(problems_of(build.bvh, mesh).empty());
      // The deepest interior node of a balanced tree of n leaves: ceil(log2 n) - 1.
      CHECK(build.bvh.stats.depth ==
            static_cast<int>(std::bit_width(static_cast<unsigned>(n - 1))) - 1);
    }
  }
}

TEST_CASE("a chain of powers of two stays within the traversal's depth bound", "[ch10]") {
  const Mesh mesh = power_of_two_chain(4096);
  const GpuBuild narrow = build_lbvh(Backend::cpu, mesh, CodeWidth::bits30);
  CHECK(problems_of(narrow.bvh, mesh).empty());
  CHECK(narrow.note.empty());
  // The chain of 30 codes, then the pile of 4096 (2^12): within the proof's bound of 57.
  CHECK(narrow.bvh.stats.depth == 42);
  // 63-bit codes would chain 63 levels above the pile: the build sees it and falls back.
  const GpuBuild wide = build_lbvh(Backend::cpu, mesh, CodeWidth::bits63);
  CHECK(wide.codes == CodeWidth::bits30);
  CHECK(!wide.note.empty());
  CHECK(problems_of(wide.bvh, mesh).empty());
  CHECK(rt::testing::same_bits(wide.bvh.nodes, narrow.bvh.nodes));
  // A shorter pile keeps the 63-bit tree under the bound: no fallback.
  const Mesh small = power_of_two_chain(0);
  const GpuBuild kept = build_lbvh(Backend::cpu, small, CodeWidth::bits63);
  CHECK(kept.codes == CodeWidth::bits63);
  // Deeper than any 30-bit tree can be (57), within the traversal stack (63).
  CHECK(kept.bvh.stats.depth == 61);
  CHECK(problems_of(kept.bvh, small).empty());
}

TEST_CASE("PLOC trees pass chapter 07's checker, give brute force's hits, cost less",
          "[ch10]") {
  for (const Vec3f centre : {Vec3f{}, Vec3f{-1e5f, 2e4f, 1e5f}}) {
    CAPTURE(centre.x);
    const Mesh scene = rt::testing::mixed_scene(3000, 13);
    Mesh moved = scene;
    for (Vec3f& v : moved.vertices) v = v + centre;
    const GpuBuild ploc = build_ploc(Backend::cpu, moved);
    CHECK(problems_of(ploc.bvh, moved).empty());
    CHECK(ploc.note.empty());
    // Nearest neighbours to speak of: every round merges its mutual pairs, none in order.
    CHECK(ploc.rounds > 0);
    CHECK(ploc.rounds_in_order == 0);
    const auto rays = rt::testing::random_rays(3000, 19, centre, 10.0f);
    CHECK(brute_force_mismatches(ploc.bvh.view(), moved, rays) == 0);
    // Merging by area beats splitting by Morton bits.
    const GpuBuild lbvh = build_lbvh(Backend::cpu, moved, CodeWidth::bits30);
    CHECK(ploc.bvh.stats.sah_cost < lbvh.bvh.stats.sah_cost);
  }
  for (const Mesh& mesh : {identical_triangles(1000), power_of_two_chain(4096),
                           rt::testing::single_triangle(), Mesh{}}) {
    const GpuBuild ploc = build_ploc(Backend::cpu, mesh, 1);
    CHECK(problems_of(ploc.bvh, mesh).empty());
  }
  CHECK_THROWS_AS(build_ploc(Backend::cpu, identical_triangles(4), 0), InputError);
}

TEST_CASE("PLOC's rounds stay few on identical, collinear and ever wider spaced centroids",
          "[ch10]") {
  // Each of these once took n - 1 rounds of one merge each, n^2 work (20 000 identical
  // triangles took half a minute on two CPU threads). Now a round of more than
  // F = k_ploc_ordered_share clusters with hardly a mutual pair pairs them all in order,
  // halving them, and at most F - 1 rounds of one merge are left: log2(n) + F rounds, well
  // inside the bound that holds for any input (293 for 200 000 triangles).
  const std::pair<const char*, Mesh> cases[] = {
      {"identical", identical_triangles(200000)},
      {"collinear, evenly spaced", collinear_triangles(100000)},
      {"collinear, spaced by 2^(1/4)", exponentially_spaced_triangles(480)},
  };
  for (const auto& [name, mesh] : cases) {
    CAPTURE(name);
    const int n = static_cast<int>(mesh.triangles.size());
    const GpuBuild ploc = build_ploc(Backend::cpu, mesh);
    CHECK(problems_of(ploc.bvh, mesh).empty());
    CHECK(ploc.note.empty()); // PLOC's own tree: no deeper than the traversal stack
    CHECK(ploc.rounds <= ploc_round_bound(n));
    CHECK(ploc.rounds <= std::bit_width(static_cast<unsigned>(n)) + k_ploc_ordered_share);
    CHECK(ploc.rounds_in_order > 0);
    // The LBVH has no rounds: its time is a sort and a pass per node whatever the input, and
    // its 30-bit tree stays within the proof's depth of 57 (gpu_build.cu).
    for (const CodeWidth width : k_widths) {
      CAPTURE(to_string(width));
      const GpuBuild lbvh = build_lbvh(Backend::cpu, mesh, width);
      CHECK(problems_of(lbvh.bvh, mesh).empty());
      CHECK(lbvh.bvh.stats.depth <= (lbvh.codes == CodeWidth::bits30 ? 57 : 63));
    }
  }
  CHECK(ploc_round_bound(200000) == 293);
  CHECK(ploc_round_bound(2) == 1);
  CHECK(ploc_round_bound(1) == 0);
}

TEST_CASE("the refit of a bent mesh passes the checker and gives brute force's hits",
          "[ch10]") {
  const Mesh scene = rt::testing::mixed_scene(1500, 29);
  const Mesh moved = bent(scene, 0.8f);
  const auto rays = rt::testing::random_rays(3000, 31, {}, 10.0f);
  for (const CodeWidth width : k_widths) {
    CAPTURE(to_string(width));
    ch07::Bvh bvh = build_lbvh(Backend::cpu, scene, width).bvh;
    const double before = bvh.stats.sah_cost;
    refit_bvh(Backend::cpu, bvh, moved);
    CHECK(problems_of(bvh, moved).empty());
    CHECK(brute_force_mismatches(bvh.view(), moved, rays) == 0);
    CHECK(bvh.stats.sah_cost != before);
    // Back to the old vertices: the old tree again, bit for bit.
    ch07::Bvh again = bvh;
    refit_bvh(Backend::cpu, again, scene);
    CHECK(
        rt::testing::same_bits(again.nodes, build_lbvh(Backend::cpu, scene, width).bvh.nodes));
  }
  // Any tree of chapter 07's layout: the SAH tree with leaves of four.
  ch07::Bvh sah = ch07::build_bvh(scene, {});
  refit_bvh(Backend::cpu, sah, moved);
  CHECK(problems_of(sah, moved).empty());
  CHECK(brute_force_mismatches(sah.view(), moved, rays) == 0);
}

TEST_CASE("no ray leaks out of a closed mesh through the LBVH, its refit or PLOC", "[ch10]") {
  for (const ch04::LeakConfiguration& config : ch04::k_leak_configurations) {
    const Mesh mesh = config.make_mesh();
    const std::vector<RayF> rays = ch04::rays_at_vertices_and_edges(
        mesh, config.inside(), config.spread, 20000, config.seed);
    ch07::Bvh bvh = build_lbvh(Backend::cpu, mesh, CodeWidth::bits30).bvh;
    // A tree built for the mesh bent out of shape, its boxes refitted to the closed mesh:
    // every box moved, and the root's bounds are the mesh's own.
    ch07::Bvh refitted = build_lbvh(Backend::cpu, bent(mesh, 0.3f), CodeWidth::bits63).bvh;
    const std::vector<ch07::BvhNode> bent_nodes = refitted.nodes;
    refit_bvh(Backend::cpu, refitted, mesh);
    CHECK(problems_of(refitted, mesh).empty());
    CHECK(rt::testing::same_bits(refitted.bounds, bvh.bounds));
    int moved = 0;
    for (std::size_t i = 0; i < bent_nodes.size(); ++i)
      for (int c = 0; c < 2; ++c)
        moved += !rt::testing::same_bits(bent_nodes[i].box[c], refitted.nodes[i].box[c]);
    CHECK(moved == static_cast<int>(2 * bent_nodes.size()));
    ch07::Bvh ploc = build_ploc(Backend::cpu, mesh).bvh;
    for (const ch07::Bvh* tree : {&bvh, &refitted, &ploc}) {
      CAPTURE(config.name);
      int leaks = 0, any_leaks = 0;
      for (const RayF& ray : rays) {
        leaks += ch07::trace_bvh<ch07::Query::closest, ch04::TriangleVariant::watertight>(
                     tree->view(), ray)
                     .triangle < 0;
        any_leaks += ch07::trace_bvh<ch07::Query::any, ch04::TriangleVariant::watertight>(
                         tree->view(), ray)
                         .triangle < 0;
      }
      CHECK(leaks == 0);
      CHECK(any_leaks == 0);
    }
  }
}

TEST_CASE("empty, one- and two-triangle meshes give valid trees", "[ch10]") {
  const Mesh empty;
  const GpuBuild none = build_lbvh(Backend::cpu, empty, CodeWidth::bits30);
  CHECK(none.bvh.nodes.empty());
  CHECK(problems_of(none.bvh, empty).empty());
  const Mesh one = rt::testing::single_triangle();
  ch07::Bvh single = build_lbvh(Backend::cpu, one, CodeWidth::bits63).bvh;
  CHECK(problems_of(single, one).empty());
  const RayF up{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  CHECK(ch07::trace_bvh<ch07::Query::closest, ch04::TriangleVariant::watertight>(single.view(),
                                                                                 up)
            .t == 3.0f);
  refit_bvh(Backend::cpu, single, bent(one, 0.1f));
  CHECK(problems_of(single, bent(one, 0.1f)).empty());
  Mesh two = one;
  ch04::append_mesh(two, bent(one, 0.5f));
  const GpuBuild pair = build_lbvh(Backend::cpu, two, CodeWidth::bits30);
  CHECK(problems_of(pair.bvh, two).empty());
  CHECK(pair.bvh.nodes.size() == 1);
}

TEST_CASE("bad input is refused with one line, never built", "[ch10]") {
  Mesh nan_vertex = rt::testing::random_soup(100, 3);
  nan_vertex.vertices[57].y = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(build_lbvh(Backend::cpu, nan_vertex, CodeWidth::bits30), InputError);
  CHECK_THROWS_WITH(build_lbvh(Backend::cpu, nan_vertex, CodeWidth::bits63),
                    Catch::Matchers::Contains("triangle 19: vertex 57 is not finite"));
  Mesh infinite = rt::testing::random_soup(10, 3);
  infinite.vertices[0].x = std::numeric_limits<float>::infinity();
  CHECK_THROWS_AS(build_lbvh(Backend::cpu, infinite, CodeWidth::bits63), InputError);
  Mesh bad_index = rt::testing::random_soup(10, 3);
  bad_index.triangles[4].v2 = 30;
  CHECK_THROWS_WITH(build_lbvh(Backend::cpu, bad_index, CodeWidth::bits30),
                    Catch::Matchers::Contains("triangle 4: vertex index 30 is out of range"));
  const Mesh scene = rt::testing::random_soup(10, 3);
  ch07::Bvh bvh = build_lbvh(Backend::cpu, scene, CodeWidth::bits30).bvh;
  CHECK_THROWS_AS(refit_bvh(Backend::cpu, bvh, nan_vertex), InputError);
  CHECK_THROWS_WITH(refit_bvh(Backend::cpu, bvh, rt::testing::random_soup(11, 3)),
                    Catch::Matchers::Contains("the mesh has 11 triangles, the tree 10"));
}
