// Chapter 09 tests of the CPU's own tree (cpu_tree.h, cpu_traverse.h): it stores the very
// boxes, children and triangles of wide8's tree; it gives brute force's hits (up to exact
// ties) near and far from the origin, from SAH and spatial-split trees, one ray at a time and
// in batches; no adversarial ray leaks; bad rays read no node; its stack stays within its
// bound on a lopsided tree; and its distances let it skip what wide8's walk reads again.
#include <algorithm>
#include <bit>
#include <limits>
#include <random>
#include <vector>

#include "rt_catch.h"

#include "07_bvh/sbvh_cases.h"
#include "adversarial_rays.h"
#include "leak_configurations.h"
#include "wide_cases.h"
#include "wide_trace.h"

using namespace rt;
using namespace rt::ch09;
using namespace rt::ch09::testing;

namespace {

// The CPU tree and wide8's of the same collapse.
struct SameCollapse {
  Wide8Bvh wide8;
  CpuTree cpu;
};

SameCollapse same_collapse(const Mesh& mesh, const ch07::BuildOptions& base = {}) {
  const WideLayout layout = build_wide_layout(mesh, 8, Collapse::sah, base);
  return {pack_wide<8>(layout), pack_cpu(layout)};
}

// The triangles a wide8 node's leaf child holds, as bits counted from its triangle_base.
unsigned wide_leaf_bits(const WideNode<8>& node, int c) {
  return is_interior_meta(node.meta[c]) ? 0u : meta_bits(node.meta[c], 0);
}

ch07::BuildOptions sbvh_options() {
  ch07::BuildOptions options;
  options.method = ch07::SplitMethod::sbvh;
  options.split_budget = 0.3;
  options.bins = 16;
  return options;
}

} // namespace

TEST_CASE("the CPU tree stores wide8's boxes, children and triangles", "[ch09]") {
  const Mesh scene = mixed_scene(2000, 31);
  const SameCollapse trees = same_collapse(scene);
  const CpuTreeView cpu = trees.cpu.view();
  const auto wide = trees.wide8.view();
  REQUIRE(cpu.node_count == wide.node_count);
  int interior = 0, leaves = 0, triangles = 0;
  for (int i = 0; i < wide.node_count; ++i) {
    CAPTURE(i);
    const WideNode<8>& w = wide.node(i);
    const CpuNode& n = cpu.node(i);
    CHECK(n.triangle_base % k_block_triangles == 0); // a node's triangles start a block
    int rank = 0; // interior children met so far, in slot order
    for (int c = 0; c < k_slots; ++c) {
      CHECK(std::bit_cast<std::uint32_t>(n.lo_x[c]) == std::bit_cast<std::uint32_t>(w.lo_x[c]));
      CHECK(std::bit_cast<std::uint32_t>(n.hi_z[c]) == std::bit_cast<std::uint32_t>(w.hi_z[c]));
      CHECK(n.lo_y[c] == w.lo_y[c]);
      CHECK(n.hi_y[c] == w.hi_y[c]);
      if (w.meta[c] == 0) { // empty: a leaf of no triangles
        CHECK(n.child[c] == cpu_leaf_child(0));
        continue;
      }
      if (is_interior_meta(w.meta[c])) {
        ++interior;
        CHECK_FALSE(is_cpu_leaf(n.child[c]));
        CHECK(n.child[c] == w.child_base + rank++);
        continue;
      }
      ++leaves;
      REQUIRE(is_cpu_leaf(n.child[c]));
      const unsigned bits = cpu_leaf_triangles(n.child[c]);
      CHECK(bits == wide_leaf_bits(w, c));
      for (unsigned left = bits; left != 0; left &= left - 1) {
        const int k = std::countr_zero(left);
        ++triangles;
        const TriangleF a = cpu.triangle(n.triangle_base + k);
        const TriangleF b = wide.triangle(w.triangle_base + k);
        CHECK((a.v0 == b.v0 && a.v1 == b.v1 && a.v2 == b.v2));
        CHECK(cpu.triangle_id(n.triangle_base + k) == wide.triangle_id(w.triangle_base + k));
      }
    }
  }
  CHECK(interior == wide.node_count - 1); // every node but the root is someone's child
  CHECK(leaves > 0);
  CHECK(triangles == static_cast<int>(scene.triangles.size()));
  CHECK(trees.cpu.stats.bytes_per_triangle > trees.wide8.stats.bytes_per_triangle);
}

TEST_CASE("the CPU tree gives brute force's hits, near and far from the origin", "[ch09]") {
  for (const float offset : {0.0f, 1e4f, 1e6f}) {
    CAPTURE(offset);
    const Vec3f centre{offset, -offset, 0.5f * offset};
    const Mesh scene = mixed_scene(2500, 33, centre);
    const std::vector<RayF> rays = rays_for(scene, 2500, 34, centre);
    const SameCollapse trees = same_collapse(scene);
    const Agreement a = against_brute_force(trees.cpu.view(), scene, rays);
    CHECK(a.closest_mismatches == 0);
    CHECK(a.any_mismatches == 0);
    CHECK(a.hits > 1000);
    // And wide8's hits on the same collapse: the same t, and the same triangle but for ties.
    int differ = 0;
    for (const RayF& ray : rays) {
      const TraceHit cpu = trace<Query::closest>(trees.cpu.view(), ray);
      const TraceHit wide = trace<Query::closest>(trees.wide8.view(), ray);
      differ += cpu.t != wide.t || (cpu.triangle < 0) != (wide.triangle < 0);
    }
    CHECK(differ == 0);
  }
}

TEST_CASE("the CPU tree from a spatial-split tree gives brute force's hits", "[ch09]") {
  // Long thin triangles across the scene: the sbvh splits them, so leaves hold clipped
  // references and a triangle may sit in several leaves.
  Mesh scene = rt::testing::long_slivers(400, 35);
  ch04::append_mesh(scene, mixed_scene(1000, 36));
  const std::vector<RayF> rays = rays_for(scene, 3000, 37);
  const SameCollapse trees = same_collapse(scene, sbvh_options());
  REQUIRE(trees.cpu.stats.references > trees.cpu.stats.triangles); // references were copied
  const Agreement a = against_brute_force(trees.cpu.view(), scene, rays);
  CHECK(a.closest_mismatches == 0);
  CHECK(a.any_mismatches == 0);
  CHECK(a.hits > 1000);
}

TEST_CASE("no ray leaks out of a closed mesh through the CPU tree", "[ch09]") {
  for (const ch04::LeakConfiguration& config : ch04::k_leak_configurations) {
    const Mesh mesh = config.make_mesh();
    const std::vector<RayF> rays = ch04::rays_at_vertices_and_edges(
        mesh, config.inside(), config.spread, 20000, config.seed);
    for (const bool spatial : {false, true}) {
      CAPTURE(config.name, spatial);
      const CpuTree tree =
          same_collapse(mesh, spatial ? sbvh_options() : ch07::BuildOptions{}).cpu;
      for (const Query query : {Query::closest, Query::any}) {
        std::vector<MeshHit> hits(rays.size());
        trace_cpu_tree(query, tree.view(), rays, hits);
        int leaks = 0;
        for (const MeshHit& hit : hits) leaks += hit.triangle < 0;
        CHECK(leaks == 0);
      }
    }
  }
}

TEST_CASE("the CPU tree's batch path gives its one-ray hits bit for bit", "[ch09]") {
  // The batch fixes the triangle test's axes per ray and, with AVX2, reads nodes and tests
  // triangles eight at a time; the one-ray walk uses chapter 04's test as it is.
  const Mesh scene = mixed_scene(1500, 38);
  const std::vector<RayF> rays = rays_for(scene, 1500, 39);
  const CpuTree tree = same_collapse(scene).cpu;
  for (const Query query : {Query::closest, Query::any}) {
    CAPTURE(query == Query::closest);
    std::vector<MeshHit> batch(rays.size());
    trace_cpu_tree(query, tree.view(), rays, batch);
    int differ = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const TraceHit one = query == Query::closest ? trace<Query::closest>(tree.view(), rays[i])
                                                   : trace<Query::any>(tree.view(), rays[i]);
      differ += batch[i].triangle != one.triangle ||
                std::bit_cast<std::uint32_t>(batch[i].t) != std::bit_cast<std::uint32_t>(one.t);
    }
    CHECK(differ == 0);
  }
}

TEST_CASE("bad rays read no node of the CPU tree, and an empty mesh has none", "[ch09]") {
  const Mesh scene = mixed_scene(300, 40);
  const CpuTree tree = same_collapse(scene).cpu;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const RayF bad[] = {{{nan, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}},
                      {{0.0f, 0.0f, -20.0f}, {0.0f, nan, 1.0f}},
                      {{k_inf, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f}},
                      {{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 0.0f}},
                      {{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 1.0f}, nan, k_inf}};
  for (const RayF& ray : bad) {
    ch07::Counters c;
    CHECK(trace<Query::closest>(tree.view(), ray, c).triangle == -1);
    CHECK(trace<Query::any>(tree.view(), ray, c).triangle == -1);
    CHECK(c.nodes == 0);
  }
  const CpuTree empty = pack_cpu(build_wide_layout(Mesh{}, 8, Collapse::sah));
  CHECK(empty.view().node_count == 0);
  CHECK(trace<Query::closest>(empty.view(), RayF{{0, 0, -1}, {0, 0, 1}}).triangle == -1);
}

TEST_CASE("the CPU tree's stack stays within its bound on a lopsided tree", "[ch09]") {
  // Triangles growing geometrically along x, as in the wide trees' test: the deepest tree
  // chapter 07's build makes of so few triangles.
  float x = 0.0f;
  const Mesh chain = geometric_chain(200, x);
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<RayF> rays;
  for (int i = 0; i < 2000; ++i) { // along the chain, from either end, slightly tilted
    const float far = 1.3f * x;
    const bool forward = i % 2 == 0;
    const Vec3f o{forward ? -1.0f : far, 0.05f * unit(rng), 0.05f * unit(rng)};
    rays.push_back({o, {forward ? 1.0f : -1.0f, 0.02f * unit(rng), 0.02f * unit(rng)}});
  }
  const CpuTree tree = same_collapse(chain).cpu;
  const ch07::TraversalWork work = measure_cpu_tree_work(Query::closest, tree.view(), rays);
  CAPTURE(tree.stats.depth, work.max_stack);
  CHECK(work.max_stack <= (k_slots - 1) * tree.stats.depth);
  CHECK(work.max_stack <= k_cpu_stack_size);
  const Agreement a = against_brute_force(tree.view(), chain, rays);
  CHECK(a.closest_mismatches == 0);
  CHECK(a.any_mismatches == 0);
}

TEST_CASE("children farther than the nearest hit are dropped unread", "[ch09]") {
  // 64 parallel squares, one behind the other along z, and rays straight at the first. The
  // nearest-first walk goes down to the first square's leaf, hits it, and every child waiting
  // on the stack lies behind the hit: the walk reads one node per level and no more. wide8's
  // walk keeps no distances: it reads each waiting group's nodes again before their boxes,
  // now beyond the hit, refuse them.
  Mesh wall;
  for (int i = 0; i < 64; ++i) {
    const int base = static_cast<int>(wall.vertices.size());
    const float z = float(i);
    wall.vertices.push_back({-1.0f, -1.0f, z});
    wall.vertices.push_back({1.0f, -1.0f, z});
    wall.vertices.push_back({1.0f, 1.0f, z});
    wall.vertices.push_back({-1.0f, 1.0f, z});
    wall.triangles.push_back({base, base + 1, base + 2});
    wall.triangles.push_back({base, base + 2, base + 3});
  }
  const SameCollapse trees = same_collapse(wall);
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> unit(-0.9f, 0.9f);
  long long cpu_nodes = 0, wide_nodes = 0;
  for (int i = 0; i < 200; ++i) {
    const RayF ray{{unit(rng), unit(rng), -5.0f}, {0.01f * unit(rng), 0.01f * unit(rng), 1.0f}};
    ch07::Counters cpu, wide;
    const TraceHit hit = trace<Query::closest>(trees.cpu.view(), ray, cpu);
    CHECK(trace<Query::closest>(trees.wide8.view(), ray, wide).t == hit.t);
    CHECK(hit.t == Approx(5.0f).epsilon(1e-3));
    CHECK(cpu.nodes <= trees.cpu.stats.depth + 1);
    cpu_nodes += cpu.nodes;
    wide_nodes += wide.nodes;
  }
  CHECK(cpu_nodes < wide_nodes);
}
