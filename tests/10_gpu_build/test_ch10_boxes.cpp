// Chapter 10 tests of the LBVH over boxes (what chapter 13's top level is built with): over the
// boxes of a mesh's triangles it is build_lbvh's 30-bit tree, node for node and bit for bit;
// every node's box is exactly the union of its children's and every box sits in one leaf, for
// one box, two, equal boxes, boxes far apart and tiny ones; points looked up through the tree
// find the boxes brute force finds; bad boxes are refused by name; a build reuses its arrays.
// On the GPU: the CPU's tree bit for bit, built once and built again on the same arrays.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "rt_catch.h"

#include "07_bvh/bvh_cases.h"
#include "build_cases.h"
#include "gpu_build.h"
#include "gpu_guard.h"
#include "rt/backend_array.h"
#include "rt/error.h"

using namespace rt;
using namespace rt::ch10;
using namespace rt::ch10::testing;
using ch07::Aabb;
using ch07::BvhNode;
using rt::testing::same_bits;

namespace {

// The box of each of the mesh's triangles, in the mesh's order.
std::vector<Aabb> triangle_boxes(const Mesh& mesh) {
  std::vector<Aabb> boxes;
  for (int i = 0; i < static_cast<int>(mesh.triangles.size()); ++i)
    boxes.push_back(ch07::bounds_of(mesh.triangle(i)));
  return boxes;
}

// `count` boxes whose centres are uniform in the cube centre +- spread, each half as wide on
// each axis as a number uniform in [smallest, largest).
std::vector<Aabb> random_boxes(int count, unsigned seed, Vec3f centre, float spread,
                               float smallest, float largest) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> where(-spread, spread), half(smallest, largest);
  std::vector<Aabb> boxes;
  for (int i = 0; i < count; ++i) {
    const Vec3f c = centre + Vec3f{where(rng), where(rng), where(rng)};
    const Vec3f h{half(rng), half(rng), half(rng)};
    Aabb box;
    box.grow(c - h);
    box.grow(c + h);
    boxes.push_back(box);
  }
  return boxes;
}

// What is wrong with `tree` as the LBVH over `boxes`: the node count, a leaf slot or node
// reached twice or never, a child out of the depth-first order, a leaf box that is not its
// box bit for bit, a node box that is not exactly the union of the child node's two boxes, a
// root that does not cover every box, a tree deeper than chapter 07's traversal stack.
std::vector<std::string> box_tree_problems(const BoxTree& tree,
                                           const std::vector<Aabb>& boxes) {
  std::vector<std::string> problems;
  const int n = static_cast<int>(boxes.size());
  const int node_count = static_cast<int>(tree.nodes.size());
  if (node_count != (n <= 1 ? n : n - 1))
    problems.push_back(std::to_string(node_count) + " nodes for " + std::to_string(n));
  if (static_cast<int>(tree.leaf_ids.size()) != n)
    problems.push_back(std::to_string(tree.leaf_ids.size()) + " leaf ids for " +
                       std::to_string(n));
  if (!problems.empty() || n == 0) return problems;
  std::vector<int> slot_seen(n, 0), node_seen(node_count, 0);
  std::vector<std::pair<int, int>> stack{{0, 0}}; // node, depth
  while (!stack.empty()) {
    const auto [i, depth] = stack.back();
    stack.pop_back();
    const std::string at = "node " + std::to_string(i) + ": ";
    if (depth > ch07::k_max_bvh_depth - 1) problems.push_back(at + "deeper than the stack");
    ++node_seen[i];
    const BvhNode& node = tree.nodes[i];
    for (int c = 0; c < 2; ++c) {
      const std::string child = at + "child " + std::to_string(c) + " ";
      if (node.count[c] == 1) {
        const int slot = node.first[c];
        if (slot < 0 || slot >= n) {
          problems.push_back(child + "names slot " + std::to_string(slot));
          continue;
        }
        ++slot_seen[slot];
        const int id = tree.leaf_ids[slot];
        if (id < 0 || id >= n)
          problems.push_back(child + "holds box " + std::to_string(id));
        else if (!same_bits(node.box[c], boxes[id]))
          problems.push_back(child + "is not box " + std::to_string(id));
      } else if (node.count[c] == 0 && n == 1) {
        if (c == 0 || node.first[c] != -1 || !node.box[c].empty())
          problems.push_back(child + "of the one-box tree is not the empty second child");
      } else if (node.count[c] == 0) {
        const int next = node.first[c];
        if (next <= i || next >= node_count || (c == 0 && next != i + 1)) {
          problems.push_back(child + "names node " + std::to_string(next));
          continue;
        }
        Aabb whole = tree.nodes[next].box[0];
        whole.grow(tree.nodes[next].box[1]);
        if (!same_bits(node.box[c], whole)) problems.push_back(child + "is not its union");
        stack.push_back({next, depth + 1});
      } else {
        problems.push_back(child + "is a leaf of " + std::to_string(node.count[c]));
      }
    }
  }
  for (int i = 0; i < node_count; ++i)
    if (node_seen[i] != 1)
      problems.push_back("node " + std::to_string(i) + " reached " +
                         std::to_string(node_seen[i]) + " times");
  for (int k = 0; k < n; ++k)
    if (slot_seen[k] != 1)
      problems.push_back("slot " + std::to_string(k) + " in " + std::to_string(slot_seen[k]) +
                         " leaves");
  std::vector<int> ids = tree.leaf_ids;
  std::sort(ids.begin(), ids.end());
  for (int k = 0; k < n; ++k)
    if (ids[k] != k) {
      problems.push_back("the leaf ids are not each box once");
      break;
    }
  Aabb all, root = tree.nodes[0].box[0];
  for (const Aabb& box : boxes) all.grow(box);
  root.grow(tree.nodes[0].box[1]);
  if (!(root.lo == all.lo && root.hi == all.hi))
    problems.push_back("the root is not the union of all boxes");
  return problems;
}

bool inside(const Aabb& box, Vec3f p) {
  return box.lo.x <= p.x && p.x <= box.hi.x && box.lo.y <= p.y && p.y <= box.hi.y &&
         box.lo.z <= p.z && p.z <= box.hi.z;
}

// The boxes that hold point p, found through the tree (entering only node boxes that hold p),
// sorted.
std::vector<int> boxes_at_through_tree(const BoxTree& tree, Vec3f p) {
  std::vector<int> found, stack;
  if (!tree.nodes.empty()) stack.push_back(0);
  while (!stack.empty()) {
    const BvhNode& node = tree.nodes[stack.back()];
    stack.pop_back();
    for (int c = 0; c < 2; ++c) {
      if (!inside(node.box[c], p)) continue;
      if (node.count[c] == 1)
        found.push_back(tree.leaf_ids[node.first[c]]);
      else if (node.count[c] == 0)
        stack.push_back(node.first[c]);
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

// The same by brute force.
std::vector<int> boxes_at(const std::vector<Aabb>& boxes, Vec3f p) {
  std::vector<int> found;
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i)
    if (inside(boxes[i], p)) found.push_back(i);
  return found;
}

// Points looked up through the tree whose boxes differ from brute force's: each box's centre,
// a corner of every seventh box, and `random_points` points uniform in the root's box.
int lookup_mismatches(const BoxTree& tree, const std::vector<Aabb>& boxes, int random_points) {
  std::vector<Vec3f> points;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    points.push_back(0.5f * boxes[i].lo + 0.5f * boxes[i].hi);
    if (i % 7 == 0) points.push_back(boxes[i].hi);
  }
  Aabb all;
  for (const Aabb& box : boxes) all.grow(box);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int k = 0; k < random_points; ++k)
    points.push_back(all.lo + Vec3f{unit(rng), unit(rng), unit(rng)} * (all.hi - all.lo));
  int mismatches = 0;
  for (const Vec3f& p : points)
    if (boxes_at_through_tree(tree, p) != boxes_at(boxes, p)) ++mismatches;
  return mismatches;
}

int depth_of(const BoxTree& tree) {
  int deepest = 0;
  std::vector<std::pair<int, int>> stack;
  if (!tree.nodes.empty()) stack.push_back({0, 0});
  while (!stack.empty()) {
    const auto [i, depth] = stack.back();
    stack.pop_back();
    deepest = std::max(deepest, depth);
    for (int c = 0; c < 2; ++c)
      if (tree.nodes[i].count[c] == 0 && tree.nodes[i].first[c] > i)
        stack.push_back({tree.nodes[i].first[c], depth + 1});
  }
  return deepest;
}

void check_same_tree(const BoxTree& a, const BoxTree& b) {
  CHECK(same_bits(a.nodes, b.nodes));
  CHECK(a.leaf_ids == b.leaf_ids);
}

} // namespace

TEST_CASE("over a mesh's triangle boxes, the LBVH over boxes is build_lbvh's 30-bit tree",
          "[ch10][lbvh-boxes]") {
  // The same passes from the same boxes: the centroids, their bounds, the codes and the sort
  // are the same, and a leaf's box, one triangle's box grown from the empty box, is the box
  // the LBVH over boxes is given. So every node is the same, boxes included, bit for bit.
  const std::vector<Mesh> meshes = {
      ch04::make_icosphere(3, {0.5, -0.25, 1.0}, 2.0),
      rt::testing::random_soup(5000, 17, Vec3f{3e4f, -1e3f, 0.0f}),
      rt::testing::mixed_scene(3000, 19),
      identical_triangles(777),  // every centroid equal
      power_of_two_chain(257),   // codes of one bit each: a chain
      collinear_triangles(1000), // centroids on a line
      rt::testing::single_triangle()};
  for (const Mesh& mesh : meshes) {
    CAPTURE(mesh.triangles.size());
    const std::vector<Aabb> boxes = triangle_boxes(mesh);
    const BoxTree tree = build_lbvh_over_boxes(Backend::cpu, boxes);
    const GpuBuild lbvh = build_lbvh(Backend::cpu, mesh, CodeWidth::bits30);
    CHECK(box_tree_problems(tree, boxes).empty());
    CHECK(tree.nodes.size() == lbvh.bvh.nodes.size());
    CHECK(same_bits(tree.nodes, lbvh.bvh.nodes));
    CHECK(tree.leaf_ids == lbvh.bvh.triangle_ids);
  }
}

TEST_CASE("the LBVH over boxes: each node box is the union of its children, each box in one "
          "leaf, and points find brute force's boxes",
          "[ch10][lbvh-boxes]") {
  struct Case {
    const char* name;
    std::vector<Aabb> boxes;
  };
  std::vector<Aabb> far_apart; // a 12 x 12 x 12 grid of unit boxes 1e5 apart
  for (int x = 0; x < 12; ++x)
    for (int y = 0; y < 12; ++y)
      for (int z = 0; z < 12; ++z) {
        const Vec3f c{1e5f * x, 1e5f * y, -1e5f * z};
        Aabb box;
        box.grow(c - Vec3f{0.5f, 0.5f, 0.5f});
        box.grow(c + Vec3f{0.5f, 0.5f, 0.5f});
        far_apart.push_back(box);
      }
  std::vector<Case> cases = {
      {"3 boxes", random_boxes(3, 1, {}, 1.0f, 0.1f, 0.5f)},
      {"overlapping boxes", random_boxes(2000, 2, {}, 10.0f, 0.5f, 3.0f)},
      {"boxes far from the origin",
       random_boxes(2000, 3, {1e5f, -1e5f, 1e5f}, 50.0f, 0.1f, 2.0f)},
      {"boxes 1e5 apart", far_apart},
      {"tiny boxes, 1e-3 wide",
       random_boxes(3000, 4, {0.25f, 0.5f, -1.0f}, 1.0f, 5e-4f, 5e-4f)},
      {"points: boxes of no width", random_boxes(500, 5, {}, 2.0f, 0.0f, 0.0f)},
      {"boxes of every size", random_boxes(3000, 6, {}, 100.0f, 1e-3f, 30.0f)}};
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const BoxTree tree = build_lbvh_over_boxes(Backend::cpu, c.boxes);
    CHECK(box_tree_problems(tree, c.boxes).empty());
    CHECK(lookup_mismatches(tree, c.boxes, 2000) == 0);
  }
}

TEST_CASE("the LBVH over boxes of none, one and two boxes", "[ch10][lbvh-boxes]") {
  const BoxTree none = build_lbvh_over_boxes(Backend::cpu, {});
  CHECK(none.nodes.empty());
  CHECK(none.leaf_ids.empty());

  // One box: chapter 07's one-leaf root, as build_lbvh makes for one triangle.
  const std::vector<Aabb> one = random_boxes(1, 7, {2.0f, 3.0f, 4.0f}, 1.0f, 0.5f, 1.0f);
  const BoxTree single = build_lbvh_over_boxes(Backend::cpu, one);
  REQUIRE(single.nodes.size() == 1);
  const BvhNode& root = single.nodes[0];
  CHECK(same_bits(root.box[0], one[0]));
  CHECK((root.first[0] == 0 && root.count[0] == 1));
  CHECK((root.first[1] == -1 && root.count[1] == 0));
  CHECK(root.box[1].empty());
  CHECK(single.leaf_ids == std::vector<int>{0});
  CHECK(box_tree_problems(single, one).empty());

  // Two boxes: one node with a leaf each, in Morton order, whichever order they come in.
  Aabb low, high;
  low.grow(Vec3f{0.0f, 0.0f, 0.0f});
  low.grow(Vec3f{1.0f, 1.0f, 1.0f});
  high.grow(Vec3f{5.0f, 5.0f, 5.0f});
  high.grow(Vec3f{7.0f, 6.0f, 8.0f});
  for (const bool reversed : {false, true}) {
    const std::vector<Aabb> two =
        reversed ? std::vector<Aabb>{high, low} : std::vector<Aabb>{low, high};
    const BoxTree tree = build_lbvh_over_boxes(Backend::cpu, two);
    REQUIRE(tree.nodes.size() == 1);
    CHECK(box_tree_problems(tree, two).empty());
    CHECK(tree.leaf_ids == (reversed ? std::vector<int>{1, 0} : std::vector<int>{0, 1}));
    CHECK(same_bits(tree.nodes[0].box[0], low));
    CHECK(same_bits(tree.nodes[0].box[1], high));
  }
}

TEST_CASE("equal boxes make a balanced LBVH over boxes, in input order", "[ch10][lbvh-boxes]") {
  // Every code equal: the sort keeps the input order and Karras's tree splits the run like the
  // binary numbers of the leaves, so the depth is that of a balanced tree.
  for (const int n : {2, 3, 1000, 4096, 5001}) {
    CAPTURE(n);
    const std::vector<Aabb> boxes(n, random_boxes(1, 8, {}, 1.0f, 0.1f, 1.0f)[0]);
    const BoxTree tree = build_lbvh_over_boxes(Backend::cpu, boxes);
    CHECK(box_tree_problems(tree, boxes).empty());
    std::vector<int> in_order(n);
    std::iota(in_order.begin(), in_order.end(), 0);
    CHECK(tree.leaf_ids == in_order);
    const int balanced = static_cast<int>(std::ceil(std::log2(static_cast<double>(n)))) - 1;
    CHECK(depth_of(tree) == balanced);
  }
}

TEST_CASE("the LBVH over boxes refuses boxes that are empty or not finite, by number",
          "[ch10][lbvh-boxes]") {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Aabb> boxes = random_boxes(10, 9, {}, 1.0f, 0.1f, 1.0f);
  const auto refused_as = [&](Aabb bad, const char* what) {
    std::vector<Aabb> damaged = boxes;
    damaged[6] = bad;
    CHECK_THROWS_WITH(build_lbvh_over_boxes(Backend::cpu, damaged),
                      rt::testing::contains("box 6 ") && rt::testing::contains(what));
  };
  Aabb with_nan = boxes[6], with_inf = boxes[6], inside_out = boxes[6];
  with_nan.lo.y = nan;
  with_inf.hi.z = inf;
  std::swap(inside_out.lo.x, inside_out.hi.x);
  refused_as(with_nan, "not finite");
  refused_as(with_inf, "not finite");
  refused_as(inside_out, "empty");
  refused_as(Aabb{}, "not finite"); // the empty box: +inf to -inf
  CHECK_NOTHROW(build_lbvh_over_boxes(Backend::cpu, boxes));
}

TEST_CASE("the checker of the LBVH over boxes names damaged trees", "[ch10][lbvh-boxes]") {
  // The checker the tests above rely on fails on each kind of damage it is meant to see.
  const std::vector<Aabb> boxes = random_boxes(200, 10, {}, 5.0f, 0.1f, 1.0f);
  const BoxTree tree = build_lbvh_over_boxes(Backend::cpu, boxes);
  REQUIRE(box_tree_problems(tree, boxes).empty());
  BoxTree swapped = tree; // two leaves trade boxes: their boxes no longer match
  std::swap(swapped.leaf_ids[3], swapped.leaf_ids[150]);
  CHECK_FALSE(box_tree_problems(swapped, boxes).empty());
  BoxTree shrunk = tree; // a node box smaller than its children's union
  shrunk.nodes[0].box[1].hi.x -= 0.5f;
  CHECK_FALSE(box_tree_problems(shrunk, boxes).empty());
  BoxTree grown = tree; // larger than the union: still holds everything, but not exact
  grown.nodes[0].box[0].lo.y -= 1.0f;
  CHECK_FALSE(box_tree_problems(grown, boxes).empty());
  BoxTree twice = tree; // one slot in two leaves, another in none
  for (BvhNode& node : twice.nodes)
    for (int c = 0; c < 2; ++c)
      if (node.count[c] == 1 && node.first[c] == 7) node.first[c] = 8;
  CHECK_FALSE(box_tree_problems(twice, boxes).empty());
  std::vector<Aabb> moved = boxes; // the tree of other boxes
  moved[42].hi.z += 1.0f;
  CHECK_FALSE(box_tree_problems(tree, moved).empty());
}

TEST_CASE("an LBVH over boxes built again on the same arrays is the fresh build's tree",
          "[ch10][lbvh-boxes]") {
  const std::vector<Aabb> first = random_boxes(3000, 11, {}, 20.0f, 0.1f, 2.0f);
  BackendArray<Aabb> d_boxes(Backend::cpu, std::span<const Aabb>(first));
  LbvhOverBoxes lbvh(Backend::cpu, 3000);
  CHECK(lbvh.capacity() == 3000);
  lbvh.build(d_boxes.data(), 3000);
  const BvhNode* nodes = lbvh.nodes();
  const int* ids = lbvh.leaf_ids();
  check_same_tree(lbvh.to_host(), build_lbvh_over_boxes(Backend::cpu, first));
  // The boxes move (each by its own offset), then fewer of them, then one, then none, then
  // all again: every build is the fresh tree of its boxes, in the same arrays.
  std::vector<Aabb> moved = first;
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> step(-3.0f, 3.0f);
  for (Aabb& box : moved) {
    const Vec3f offset{step(rng), step(rng), step(rng)};
    box.lo = box.lo + offset;
    box.hi = box.hi + offset;
  }
  BackendArray<Aabb> d_moved(Backend::cpu, std::span<const Aabb>(moved));
  for (const int count : {3000, 1000, 2, 1, 0, 3000}) {
    CAPTURE(count);
    lbvh.build(d_moved.data(), count);
    CHECK(lbvh.count() == count);
    CHECK(lbvh.node_count() == (count <= 1 ? count : count - 1));
    const std::vector<Aabb> given(moved.begin(), moved.begin() + count);
    check_same_tree(lbvh.to_host(), build_lbvh_over_boxes(Backend::cpu, given));
    CHECK(box_tree_problems(lbvh.to_host(), given).empty());
  }
  CHECK(lbvh.nodes() == nodes);
  CHECK(lbvh.leaf_ids() == ids);
  CHECK_THROWS_AS(lbvh.build(d_moved.data(), 3001), UsageError);
  CHECK_THROWS_AS(LbvhOverBoxes(Backend::cpu, -1), UsageError);
}

TEST_CASE("the GPU's LBVH over boxes is the CPU's, bit for bit, built once and again",
          "[ch10][lbvh-boxes][gpu]") {
  RT_REQUIRE_GPU();
  for (const int n : {1, 2, 1000, 100000}) {
    CAPTURE(n);
    const std::vector<Aabb> boxes =
        random_boxes(n, 13, {-50.0f, 1e3f, 7.0f}, 100.0f, 0.01f, 3.0f);
    const BoxTree gpu = build_lbvh_over_boxes(Backend::gpu, boxes);
    check_same_tree(gpu, build_lbvh_over_boxes(Backend::cpu, boxes));
    CHECK(box_tree_problems(gpu, boxes).empty());
  }
  // Equal boxes and a mesh's triangle boxes, against the CPU's and against build_lbvh's tree.
  const std::vector<Aabb> equal(20000, random_boxes(1, 14, {}, 1.0f, 0.1f, 1.0f)[0]);
  check_same_tree(build_lbvh_over_boxes(Backend::gpu, equal),
                  build_lbvh_over_boxes(Backend::cpu, equal));
  const Mesh mesh = rt::testing::mixed_scene(20000, 41);
  const BoxTree from_mesh = build_lbvh_over_boxes(Backend::gpu, triangle_boxes(mesh));
  const GpuBuild lbvh = build_lbvh(Backend::gpu, mesh, CodeWidth::bits30);
  CHECK(same_bits(from_mesh.nodes, lbvh.bvh.nodes));
  CHECK(from_mesh.leaf_ids == lbvh.bvh.triangle_ids);

  // One object, its arrays reused: the boxes move every build, and their count changes.
  constexpr int capacity = 100000;
  std::vector<Aabb> boxes = random_boxes(capacity, 15, {}, 500.0f, 0.1f, 5.0f);
  LbvhOverBoxes on_gpu(Backend::gpu, capacity);
  BackendArray<Aabb> d_boxes(Backend::gpu, std::span<const Aabb>(boxes));
  std::mt19937 rng(16);
  std::uniform_real_distribution<float> step(-20.0f, 20.0f);
  for (const int count : {capacity, capacity, 1000, 2, 1, 0, capacity}) {
    CAPTURE(count);
    for (Aabb& box : boxes) {
      const Vec3f offset{step(rng), step(rng), step(rng)};
      box.lo = box.lo + offset;
      box.hi = box.hi + offset;
    }
    d_boxes = BackendArray<Aabb>(Backend::gpu, std::span<const Aabb>(boxes));
    on_gpu.build(d_boxes.data(), count);
    const std::vector<Aabb> given(boxes.begin(), boxes.begin() + count);
    const BoxTree gpu = on_gpu.to_host();
    check_same_tree(gpu, build_lbvh_over_boxes(Backend::cpu, given));
    CHECK(box_tree_problems(gpu, given).empty());
  }
}
