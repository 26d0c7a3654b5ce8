// Chapter 09 tests of the wide trees' structure: every layout of every collapse passes the
// checker (each triangle in one leaf, child boxes containing their subtrees' exact boxes, child
// counts, meta bytes and masks consistent, depth within the stack's bound); the checker names
// damaged trees; quantisation rounds outward and tightly at every scale; the SAH collapse is
// never worse than the greedy one on the same binary tree; the meta encoding orders children
// by octant; degenerate meshes.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "bvh_build.h"
#include "collapse.h"
#include "rt/error.h"
#include "wide_cases.h"

using namespace rt;
using namespace rt::ch09;
using namespace rt::ch09::testing;

namespace {

template <class Node, class Triangles>
void require_valid(const WideTree<Node, Triangles>& tree, const Mesh& mesh) {
  const std::vector<std::string> problems = check_wide_tree(tree, mesh);
  for (const std::string& p : problems) UNSCOPED_INFO(p);
  CHECK(problems.empty());
}

// The problems the checker finds in `tree` after `damage`.
template <class Node, class Damage>
std::vector<std::string> damaged(WideTree<Node> tree, const Mesh& mesh, Damage damage) {
  damage(tree);
  return check_wide_tree(tree, mesh);
}

bool mentions(const std::vector<std::string>& problems, const std::string& text) {
  for (const std::string& p : problems)
    if (p.find(text) != std::string::npos) return true;
  return false;
}

// The first child position of `node` that is a leaf (meta not interior and not 0), or -1.
template <class Node> int first_leaf(const Node& node) {
  for (int c = 0; c < Node::k_width; ++c)
    if (node.meta[c] != 0 && !is_interior_meta(node.meta[c])) return c;
  return -1;
}

// The nodes of `tree` with at least one leaf child.
template <class Node> std::vector<int> nodes_with_leaves(const WideTree<Node>& tree) {
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(tree.nodes.size()); ++i)
    if (first_leaf(tree.nodes[i]) >= 0) out.push_back(i);
  return out;
}

} // namespace

TEST_CASE("every layout of every collapse passes the checker", "[ch09]") {
  const Mesh scene = mixed_scene(2500, 3);
  for (const Collapse method : {Collapse::sah, Collapse::greedy}) {
    CAPTURE(to_string(method));
    const WideLayout four = build_wide_layout(scene, 4, method);
    const WideLayout eight = build_wide_layout(scene, 8, method);
    require_valid(pack_wide<4>(four), scene);
    require_valid(pack_wide<8>(eight), scene);
    const CompressedBvh compressed = compress(eight);
    require_valid(compressed, scene);
    // Children per node within the width, and most nodes well filled.
    CHECK(four.stats.children_per_node <= 4.0);
    CHECK(four.stats.children_per_node > 2.5);
    CHECK(eight.stats.children_per_node <= 8.0);
    CHECK(eight.stats.children_per_node > 4.0);
    CHECK(eight.stats.triangles_per_leaf >= 1.0);
    CHECK(eight.stats.triangles_per_leaf <= 3.0);
    CHECK(eight.stats.depth < four.stats.depth);
    CHECK(eight.stats.depth <= k_wide_stack_size);
    // The layouts' sizes: 80-byte nodes are what makes the compressed tree small.
    CHECK(compressed.stats.bytes_per_triangle < pack_wide<8>(eight).stats.bytes_per_triangle);
    CHECK(compressed.triangles.size() == 3 * scene.triangles.size());
  }
}

TEST_CASE("the same mesh far from the origin gives valid compressed trees", "[ch09]") {
  for (const float offset : {1e4f, 1e5f, 1e6f, -3e7f}) {
    CAPTURE(offset);
    const Mesh scene = mixed_scene(800, 5, {offset, -offset, 0.5f * offset});
    require_valid(compress(build_wide_layout(scene, 8, Collapse::sah)), scene);
    require_valid(compress(build_wide_layout(scene, 8, Collapse::greedy)), scene);
  }
}

TEST_CASE("the checker names damaged trees", "[ch09]") {
  const Mesh scene = mixed_scene(600, 9);
  const CompressedBvh tree = compress(build_wide_layout(scene, 8, Collapse::sah));
  REQUIRE(check_wide_tree(tree, scene).empty());
  REQUIRE(tree.nodes.size() > 10);

  // A box shrunk by one grid step no longer contains its triangles (or its subtree).
  CHECK(mentions(damaged(tree, scene,
                         [](CompressedBvh& t) {
                           for (CompressedNode& n : t.nodes)
                             for (int c = 0; c < k_slots; ++c)
                               if (n.meta[c] != 0 && n.q_hi_x[c] > n.q_lo_x[c]) --n.q_hi_x[c];
                         }),
                 "does not contain"));
  // An interior child whose slot imask does not name.
  CHECK(mentions(damaged(tree, scene, [](CompressedBvh& t) { t.nodes[0].imask = 0; }),
                 "imask lacks"));
  // Two leaves sharing triangle bits.
  CHECK(mentions(damaged(tree, scene,
                         [](CompressedBvh& t) {
                           for (CompressedNode& n : t.nodes) {
                             int leaves[2], found = 0;
                             for (int c = 0; c < k_slots && found < 2; ++c)
                               if (n.meta[c] != 0 && !is_interior_meta(n.meta[c]))
                                 leaves[found++] = c;
                             if (found == 2) {
                               n.meta[leaves[1]] = n.meta[leaves[0]];
                               return;
                             }
                           }
                         }),
                 "overlap"));
  // A triangle id written twice, and so another missing.
  CHECK(mentions(damaged(tree, scene,
                         [](CompressedBvh& t) {
                           t.triangles[0].w = t.triangles[3].w; // record 0 takes record 1's id
                         }),
                 "in two leaves"));
  // A child base beyond the nodes.
  CHECK(mentions(damaged(tree, scene,
                         [](CompressedBvh& t) {
                           t.nodes[0].child_base = static_cast<int>(t.nodes.size());
                         }),
                 "outside"));
  // A node's leaves moved onto another node's triangles: records in two leaves and in none.
  const std::vector<int> with_leaves = nodes_with_leaves(tree);
  REQUIRE(with_leaves.size() >= 2);
  CHECK(mentions(damaged(tree, scene,
                         [&](CompressedBvh& t) {
                           t.nodes[with_leaves[0]].triangle_base =
                               t.nodes[with_leaves[1]].triangle_base;
                         }),
                 "in no leaf"));
  // And the float layout: a leaf box that misses its triangles.
  const Wide8Bvh wide = pack_wide<8>(build_wide_layout(scene, 8, Collapse::sah));
  CHECK(mentions(damaged(wide, scene,
                         [](Wide8Bvh& t) {
                           const int node = nodes_with_leaves(t).front();
                           const int c = first_leaf(t.nodes[node]);
                           t.nodes[node].lo_y[c] = t.nodes[node].hi_y[c] + 1.0f;
                         }),
                 "does not contain"));
}

TEST_CASE("quantisation rounds outward, and tightly, at every scale", "[ch09]") {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int boxes = 0;
  for (const float scale : {1e-30f, 1e-6f, 1.0f, 1e3f, 1e20f})
    for (const float offset : {0.0f, 1.0f, -7.5f, 1e5f, -3e7f, 1e30f})
      for (int k = 0; k < 40; ++k) {
        // A node box [lo, hi] and a child box inside it.
        const float lo = offset + scale * (unit(rng) - 0.5f);
        const float hi = k % 10 == 0 ? lo : lo + scale * unit(rng) * 10.0f;
        const float a = lo + (hi - lo) * unit(rng), b = lo + (hi - lo) * unit(rng);
        const float child_lo = std::max(lo, std::min(a, b)),
                    child_hi = std::min(hi, std::max(a, b));
        CAPTURE(scale, offset, lo, hi, child_lo, child_hi);
        const AxisGrid grid = choose_grid(lo, hi);
        const float step = grid.step();
        CHECK(grid.origin == lo);
        CHECK(dequantise(255, step, lo) >= hi);
        const std::uint8_t q_lo = quantise_lo(child_lo, grid);
        const std::uint8_t q_hi = quantise_hi(child_hi, grid);
        // Outward: the dequantised planes enclose the child...
        CHECK(dequantise(q_lo, step, lo) <= child_lo);
        CHECK(dequantise(q_hi, step, lo) >= child_hi);
        // ... and tightly: one step more inward would not.
        if (q_lo < 255)
          CHECK(dequantise(static_cast<std::uint8_t>(q_lo + 1), step, lo) > child_lo);
        if (q_hi > 0)
          CHECK(dequantise(static_cast<std::uint8_t>(q_hi - 1), step, lo) < child_hi);
        CHECK(dequantise(q_lo, step, lo) <= dequantise(q_hi, step, lo));
        ++boxes;
      }
  CHECK(boxes == 5 * 6 * 40);
}

TEST_CASE("the grid: flat, denormal and the widest boxes", "[ch09]") {
  const float denormal = std::numeric_limits<float>::denorm_min();
  // A flat box: the finest grid, every plane of which is the box's coordinate.
  const AxisGrid flat = choose_grid(2.5f, 2.5f);
  CHECK(flat.exponent == k_min_grid_exponent + 127);
  CHECK(dequantise(quantise_lo(2.5f, flat), flat.step(), 2.5f) == 2.5f);
  CHECK(dequantise(quantise_hi(2.5f, flat), flat.step(), 2.5f) == 2.5f);
  const AxisGrid tiny = choose_grid(-denormal, 3 * denormal);
  CHECK(dequantise(quantise_hi(3 * denormal, tiny), tiny.step(), -denormal) >= 3 * denormal);
  CHECK(dequantise(quantise_lo(denormal, tiny), tiny.step(), -denormal) <= denormal);
  // A node spanning the whole float range cannot be quantised: refused with a clear error.
  const float big = std::numeric_limits<float>::max();
  CHECK_THROWS_AS(choose_grid(-big, big), InputError);
  const AxisGrid wide = choose_grid(-1e38f, 1e38f); // wide but within the grid's reach
  CHECK(dequantise(255, wide.step(), -1e38f) >= 1e38f);
}

TEST_CASE("the SAH collapse is never worse than the greedy one on the same tree", "[ch09]") {
  // The greedy collapse of a binary tree is one of the trees the dynamic programming weighs, so
  // the SAH collapse's cost can only be lower or equal.
  for (const unsigned seed : {1u, 2u, 3u}) {
    const Mesh scene = mixed_scene(1500, seed);
    const ch07::Bvh binary = ch07::build_bvh(scene, binary_options(Collapse::sah, {}));
    for (const int width : {2, 4, 8}) {
      CAPTURE(seed, width);
      const WideLayout sah = collapse(binary, width, Collapse::sah);
      const WideLayout greedy = collapse(binary, width, Collapse::greedy);
      CHECK(sah.stats.sah_cost <= greedy.stats.sah_cost * (1.0 + 1e-12));
      require_valid(pack_wide<8>(sah), scene);
    }
  }
}

TEST_CASE("the meta byte orders interior children by the ray's octant", "[ch09]") {
  for (unsigned octant = 0; octant < 8; ++octant) {
    const unsigned inverse = 7u - octant;
    for (int s = 0; s < k_slots; ++s) {
      const unsigned bits = meta_bits(interior_meta(s), inverse);
      REQUIRE(bits != 0);
      CHECK((bits & (bits - 1)) == 0); // one bit
      const int bit = 31 - std::countl_zero(bits);
      // Visited in the order s ^ octant: the octant's own slot first (the highest bit).
      CHECK(31 - bit == (s ^ int(octant)));
    }
  }
  // A leaf's bits are its triangles', whatever the octant.
  CHECK(meta_bits(leaf_meta(3, 5), 0) == 0b111u << 5);
  CHECK(meta_bits(leaf_meta(3, 5), 7) == 0b111u << 5);
  CHECK(meta_bits(leaf_meta(1, 23), 3) == 1u << 23);
  CHECK(meta_bits(0, 5) == 0u);
  CHECK(!is_interior_meta(leaf_meta(3, 21)));
  CHECK(!is_interior_meta(leaf_meta(1, 23)));
  CHECK(!is_interior_meta(0));
}

TEST_CASE("degenerate meshes: none, one and two triangles, all centroids equal", "[ch09]") {
  Mesh one;
  one.vertices = {{-1.0f, -1.0f, 3.0f}, {1.0f, -1.0f, 3.0f}, {0.0f, 1.0f, 3.0f}};
  one.triangles = {{0, 1, 2}};
  Mesh two = one;
  two.vertices.push_back({0.0f, 0.0f, 5.0f});
  two.triangles.push_back({0, 1, 3});
  Mesh same_centroid; // 40 triangles of different shapes, every one centred on (1, 2, 3)
  for (int i = 0; i < 40; ++i) {
    const float s = 0.1f * float(i + 1);
    const int base = static_cast<int>(same_centroid.vertices.size());
    same_centroid.vertices.push_back({1.0f - s, 2.0f - s, 3.0f});
    same_centroid.vertices.push_back({1.0f + s, 2.0f - s, 3.0f + s});
    same_centroid.vertices.push_back({1.0f, 2.0f + s, 3.0f - s});
    same_centroid.triangles.push_back({base, base + 1, base + 2});
  }
  const Mesh empty;
  for (const Mesh* mesh : std::vector<const Mesh*>{&empty, &one, &two, &same_centroid}) {
    CAPTURE(mesh->triangles.size());
    const WideTrees trees = all_wide_trees(*mesh);
    require_valid(trees.wide4_sah, *mesh);
    require_valid(trees.wide4_greedy, *mesh);
    require_valid(trees.wide8_sah, *mesh);
    require_valid(trees.compressed_sah, *mesh);
    require_valid(trees.compressed_greedy, *mesh);
    require_valid(trees.wide4_packed, *mesh);
    CHECK(trees.compressed_sah.nodes.empty() == mesh->triangles.empty());
    const std::vector<RayF> rays = rays_for(*mesh, 300, 5, {1.0f, 2.0f, 3.0f});
    for_each_tree(trees, [&](const char* name, const auto& view) {
      CAPTURE(name);
      const Agreement a = against_brute_force(view, *mesh, rays);
      CHECK(a.closest_mismatches == 0);
      CHECK(a.any_mismatches == 0);
    });
  }
  // The single triangle: a root with one leaf.
  const CompressedBvh single = compress(build_wide_layout(one, 8, Collapse::sah));
  REQUIRE(single.nodes.size() == 1);
  CHECK(single.nodes[0].meta[0] == leaf_meta(1, 0));
  const TraceHit hit =
      trace<Query::closest>(single.view(), RayF{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}});
  CHECK(hit.triangle == 0);
  CHECK(hit.t == 3.0f);
}

TEST_CASE("a collapse refuses binary leaves too large for a wide leaf", "[ch09]") {
  const Mesh scene = random_soup(200, 4);
  ch07::BuildOptions four;
  four.method = ch07::SplitMethod::median; // halves down to leaves of 3 and 4
  four.max_leaf_size = 4;
  const ch07::Bvh binary = ch07::build_bvh(scene, four);
  REQUIRE(binary.stats.leaf_sizes[4] > 0);
  CHECK_THROWS_AS(collapse(binary, 8, Collapse::greedy), InputError);
  CHECK_THROWS_AS(collapse(binary, 8, Collapse::sah), InputError);
  CHECK_THROWS_AS(
      collapse(ch07::build_bvh(scene, binary_options(Collapse::sah, {})), 9, Collapse::sah),
      InputError);
}

TEST_CASE("both triangle stores read back the coordinates and id they were written with",
          "[ch09]") {
  const TriangleF triangle{{1.5f, -2.0f, 3.25f}, {-0.0f, 1e-30f, 7.0f}, {1e30f, -5.5f, 0.125f}};
  const auto same_bits = [](const TriangleF& a, const TriangleF& b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
  };
  for (const int id : {0, 1, 123456789, -1, 0x7fc00001, std::numeric_limits<int>::min()}) {
    CAPTURE(id);
    AlignedTriangles::Record aligned[AlignedTriangles::k_records];
    AlignedTriangles::write(aligned, triangle, id);
    CHECK(same_bits(AlignedTriangles::triangle(aligned), triangle));
    CHECK(AlignedTriangles::id(aligned) == id);
    PackedTriangles::Record packed[PackedTriangles::k_records];
    PackedTriangles::write(packed, triangle, id);
    CHECK(same_bits(PackedTriangles::triangle(packed), triangle));
    CHECK(PackedTriangles::id(packed) == id);
  }
  static_assert(sizeof(PackedTriangles::Record) * PackedTriangles::k_records == 40);
  static_assert(sizeof(AlignedTriangles::Record) * AlignedTriangles::k_records == 48);
}
