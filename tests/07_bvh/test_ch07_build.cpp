// Chapter 07 tests of the BVH build on the CPU: valid trees for both split methods over leaf
// sizes and bin counts, the exact layout of small trees, the checker catching each kind of
// damage, the degenerate inputs that hang or overflow naive builders, the depth bound, scale
// (1e-30 to 2e38, and far from the origin), SAH quality against the median, stats, bad input.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "bvh_cases.h"

#include "bvh_build.h"
#include "check_bvh.h"
#include "mesh_gen.h"
#include "rt/error.h"

using namespace rt;
using namespace rt::ch07;
using rt::testing::options_of;

namespace {

constexpr int k_deepest = k_max_bvh_depth - 1; // the deepest an interior node may sit

void add_triangle(ch04::Mesh& mesh, Vec3f a, Vec3f b, Vec3f c) {
  const int first = static_cast<int>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), {a, b, c});
  mesh.triangles.push_back({first, first + 1, first + 2});
}

// Triangles scattered in the cube [-1, 1]^3 with sizes from 1e-5 to 0.2 (log-uniform), so
// that small and large boxes mix and overlap, as in a real scene.
ch04::Mesh log_sized_soup(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> log_size(-5.0, std::log10(0.2));
  ch04::Mesh mesh;
  for (int i = 0; i < count; ++i) {
    const Vec3d centre{unit(rng), unit(rng), unit(rng)};
    const double size = std::pow(10.0, log_size(rng));
    Vec3f v[3];
    for (Vec3f& p : v) p = (centre + size * Vec3d{unit(rng), unit(rng), unit(rng)}).as<float>();
    add_triangle(mesh, v[0], v[1], v[2]);
  }
  return mesh;
}

// Every coordinate times 2^exponent: exact in float while nothing overflows or underflows.
ch04::Mesh scaled_by_power_of_two(ch04::Mesh mesh, int exponent) {
  for (Vec3f& p : mesh.vertices) {
    p = {std::ldexp(p.x, exponent), std::ldexp(p.y, exponent), std::ldexp(p.z, exponent)};
  }
  return mesh;
}

ch04::Mesh translated(ch04::Mesh mesh, Vec3f offset) {
  for (Vec3f& p : mesh.vertices) p += offset;
  return mesh;
}

bool has_problem(const std::vector<std::string>& problems, const std::string& text) {
  return std::any_of(problems.begin(), problems.end(), [&](const std::string& line) {
    return line.find(text) != std::string::npos;
  });
}

std::string all_lines(const std::vector<std::string>& problems) {
  std::string text;
  for (const std::string& line : problems) text += line + "\n";
  return text;
}

double half_area_double(const Aabb& box) {
  if (box.empty()) return 0.0;
  const double x = static_cast<double>(box.hi.x) - box.lo.x;
  const double y = static_cast<double>(box.hi.y) - box.lo.y;
  const double z = static_cast<double>(box.hi.z) - box.lo.z;
  return x * y + y * z + z * x;
}

// What a walk of the tree finds, counted here rather than trusted from the build.
struct TreeFacts {
  int nodes = 0;
  int leaves = 0;
  int depth = 0;
  std::vector<long long> leaf_sizes;
  bool leaves_in_depth_first_order = true; // each leaf starts where the previous one ended
  bool boxes_tight = true;                 // each child box is exactly its contents' bounds
  bool depth_invariant = true;             // depth + halving_levels(n) <= 63 at every node
  double sah = 0.0;
};

// Returns the number of triangles below `node`. Only for trees check_bvh accepted: the
// recursion trusts the layout.
int walk(const Bvh& bvh, int node_index, int depth, TreeFacts& facts, int& next_slot) {
  const BvhNode& node = bvh.nodes[node_index];
  const double root_area = half_area_double(bvh.bounds);
  const auto probability = [&](const Aabb& box) {
    return root_area > 0.0 ? half_area_double(box) / root_area : 1.0;
  };
  Aabb own = node.box[0];
  own.grow(node.box[1]);
  facts.sah += probability(node_index == 0 ? bvh.bounds : own);
  ++facts.nodes;
  facts.depth = std::max(facts.depth, depth);
  int below = 0;
  for (int c = 0; c < 2; ++c) {
    const int first = node.first[c];
    const int count = node.count[c];
    Aabb contents;
    if (count > 0) {
      ++facts.leaves;
      ++facts.leaf_sizes[count];
      facts.leaves_in_depth_first_order &= first == next_slot;
      next_slot = first + count;
      for (int k = first; k < first + count; ++k) contents.grow(bounds_of(bvh.triangles[k]));
      facts.sah += probability(node.box[c]) * count;
      below += count;
    } else if (first == -1) {
      continue; // the empty child of a root that is one leaf; check_bvh vouched for its box
    } else {
      below += walk(bvh, first, depth + 1, facts, next_slot);
      contents = bvh.nodes[first].box[0];
      contents.grow(bvh.nodes[first].box[1]);
    }
    facts.boxes_tight &= contents.lo == node.box[c].lo && contents.hi == node.box[c].hi;
  }
  facts.depth_invariant &=
      depth + halving_levels(below, bvh.options.max_leaf_size) <= k_deepest;
  return below;
}

TreeFacts facts_of(const Bvh& bvh) {
  TreeFacts facts;
  facts.leaf_sizes.assign(bvh.options.max_leaf_size + 1, 0);
  int next_slot = 0;
  if (!bvh.nodes.empty()) walk(bvh, 0, 0, facts, next_slot);
  facts.leaves_in_depth_first_order &= next_slot == static_cast<int>(bvh.triangles.size());
  return facts;
}

// Everything a good tree satisfies, checked both by check_bvh and by this file's own walk.
void require_valid(const Bvh& bvh, const ch04::Mesh& mesh) {
  const std::vector<std::string> problems = check_bvh(bvh, mesh);
  INFO(all_lines(problems));
  REQUIRE(problems.empty());
  const TreeFacts facts = facts_of(bvh);
  CHECK(facts.depth <= k_deepest);
  CHECK(facts.leaves_in_depth_first_order);
  CHECK(facts.boxes_tight);
  CHECK(facts.depth_invariant);
  CHECK(facts.nodes == bvh.stats.nodes);
  CHECK(facts.leaves == bvh.stats.leaves);
  CHECK(facts.depth == bvh.stats.depth);
  CHECK(facts.leaf_sizes == bvh.stats.leaf_sizes);
  CHECK(facts.sah == Approx(bvh.stats.sah_cost).epsilon(1e-12));
}

// Builds with both methods, leaf sizes 1, 4 and 8 and a few bin counts; every tree must be
// valid. Returns nothing: a build that does not terminate fails the test by its time limit.
void require_every_build_valid(const ch04::Mesh& mesh, std::vector<int> bin_counts = {2, 16}) {
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    for (const int leaf : {1, 4, 8}) {
      for (const int bins : bin_counts) {
        INFO(to_string(method) << ", leaf size " << leaf << ", " << bins << " bins");
        const Bvh bvh = build_bvh(mesh, options_of(method, leaf, bins));
        require_valid(bvh, mesh);
        CHECK(bvh.stats.leaf_sizes.size() == static_cast<std::size_t>(leaf + 1));
      }
    }
  }
}

std::string input_error_of(const ch04::Mesh& mesh, const BuildOptions& options) {
  try {
    build_bvh(mesh, options);
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no InputError)";
}

} // namespace

TEST_CASE("the split methods have the names the command line uses", "[ch07]") {
  CHECK(std::string(to_string(SplitMethod::median)) == "median");
  CHECK(std::string(to_string(SplitMethod::sah)) == "sah");
}

TEST_CASE("both methods build valid trees for every leaf size and bin count", "[ch07]") {
  const std::vector<ch04::Mesh> meshes = {
      log_sized_soup(3000, 7), log_sized_soup(500, 8),
      ch04::make_icosphere(3, {0.5, -0.25, 2.0}, 1.5),
      ch04::make_box({-1.0, -2.0, -3.0}, {4.0, 5.0, 6.0}, 6)};
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    INFO("mesh " << m << " of " << meshes[m].triangles.size() << " triangles");
    require_every_build_valid(meshes[m], {2, 16, 64});
  }
}

TEST_CASE("the build is deterministic", "[ch07]") {
  const ch04::Mesh mesh = log_sized_soup(2000, 11);
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    const Bvh a = build_bvh(mesh, options_of(method, 4));
    const Bvh b = build_bvh(mesh, options_of(method, 4));
    REQUIRE(a.nodes.size() == b.nodes.size());
    CHECK(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNode)) == 0);
    CHECK(a.triangle_ids == b.triangle_ids);
  }
}

TEST_CASE("four triangles in a row give the expected depth-first tree", "[ch07]") {
  // Unit triangles at x = 20, 0, 30, 10 (mesh order): sorted by x they are 1, 3, 0, 2.
  ch04::Mesh mesh;
  for (const float x : {20.0f, 0.0f, 30.0f, 10.0f}) {
    add_triangle(mesh, {x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0});
  }
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    INFO(to_string(method));
    const Bvh bvh = build_bvh(mesh, options_of(method, 1, 2));
    require_valid(bvh, mesh);
    REQUIRE(bvh.nodes.size() == 3);
    CHECK(bvh.triangle_ids == std::vector<int>{1, 3, 0, 2});
    const BvhNode& root = bvh.nodes[0];
    CHECK(root.first[0] == 1);
    CHECK(root.count[0] == 0);
    CHECK(root.first[1] == 2);
    CHECK(root.count[1] == 0);
    CHECK(root.box[0].lo == Vec3f{0, 0, 0});
    CHECK(root.box[0].hi == Vec3f{11, 1, 0});
    CHECK(root.box[1].lo == Vec3f{20, 0, 0});
    CHECK(root.box[1].hi == Vec3f{31, 1, 0});
    for (int node = 1; node <= 2; ++node) {
      for (int c = 0; c < 2; ++c) {
        CHECK(bvh.nodes[node].count[c] == 1);
        CHECK(bvh.nodes[node].first[c] == 2 * (node - 1) + c);
      }
    }
    CHECK(bvh.stats.nodes == 3);
    CHECK(bvh.stats.leaves == 4);
    CHECK(bvh.stats.depth == 1);
    CHECK(bvh.stats.leaf_sizes == std::vector<long long>{0, 4});
  }
}

TEST_CASE("check_bvh reports each kind of damage", "[ch07]") {
  const ch04::Mesh mesh = log_sized_soup(1000, 3);
  const Bvh good = build_bvh(mesh, options_of(SplitMethod::sah, 4));
  REQUIRE(check_bvh(good, mesh).empty());
  REQUIRE(good.nodes.size() > 4);
  REQUIRE(good.nodes[0].count[0] == 0); // the root's child 0 is node 1
  const auto problems_after = [&](auto&& damage) {
    Bvh bvh = good;
    damage(bvh);
    return check_bvh(bvh, mesh);
  };
  const auto first_leaf = [](const Bvh& bvh) {
    for (int i = 0; i < static_cast<int>(bvh.nodes.size()); ++i) {
      for (int c = 0; c < 2; ++c) {
        if (bvh.nodes[i].count[c] > 0) return std::pair{i, c};
      }
    }
    return std::pair{-1, -1};
  };

  SECTION("a triangle copy that differs from the mesh in one bit") {
    const auto problems = problems_after(
        [](Bvh& bvh) { bvh.triangles[5].v1.y = std::nextafter(bvh.triangles[5].v1.y, 10.0f); });
    CHECK(has_problem(problems, "triangle copy 5 differs"));
  }
  SECTION("a child box one step too small") {
    const auto problems = problems_after([&](Bvh& bvh) {
      const auto [node, c] = first_leaf(bvh);
      bvh.nodes[node].box[c].hi.x = std::nextafter(bvh.nodes[node].box[c].hi.x, -10.0f);
    });
    CHECK(has_problem(problems, "box does not contain triangle copy"));
  }
  SECTION("an interior child's box that misses part of its node") {
    const auto problems = problems_after([](Bvh& bvh) { bvh.nodes[0].box[0].lo.z += 0.01f; });
    CHECK(has_problem(problems, "node 0 child 0: box does not contain the box of node 1"));
  }
  SECTION("a triangle in two leaves, another in none") {
    const auto problems = problems_after([](Bvh& bvh) {
      bvh.triangle_ids[0] = bvh.triangle_ids[1];
      bvh.triangles[0] = bvh.triangles[1];
    });
    CHECK(has_problem(problems, "is in two leaves"));
    CHECK(has_problem(problems, "1 mesh triangles are in no leaf"));
  }
  SECTION("a leaf larger than the leaf size") {
    const auto problems = problems_after([&](Bvh& bvh) {
      const auto [node, c] = first_leaf(bvh);
      bvh.nodes[node].count[c] = 5;
    });
    CHECK(has_problem(problems, "more than 4"));
  }
  SECTION("a leaf that runs past the triangle array") {
    const auto problems = problems_after([&](Bvh& bvh) {
      const auto [node, c] = first_leaf(bvh);
      const int size = static_cast<int>(bvh.triangles.size());
      bvh.nodes[node].first[c] = size - bvh.nodes[node].count[c] + 1;
    });
    CHECK(has_problem(problems, "names triangles"));
  }
  SECTION("an interior child 0 that is not the next node") {
    const auto problems = problems_after([](Bvh& bvh) { bvh.nodes[0].first[0] = 2; });
    CHECK(has_problem(problems, "not the next node 1"));
  }
  SECTION("a child 1 that points back up the tree") {
    const auto problems = problems_after([](Bvh& bvh) {
      bvh.nodes[1].first[1] = 0;
      bvh.nodes[1].count[1] = 0;
    });
    CHECK(has_problem(problems, "node 1 child 1 is node 0, outside (1, "));
  }
  SECTION("two children naming the same node") {
    const auto problems = problems_after([](Bvh& bvh) {
      bvh.nodes[0].first[1] = 1;
      bvh.nodes[0].count[1] = 0;
      bvh.nodes[0].box[1] = bvh.nodes[0].box[0];
    });
    CHECK(has_problem(problems, "node 1 is reached twice"));
  }
  SECTION("a node nothing points to") {
    const auto problems = problems_after([](Bvh& bvh) { bvh.nodes.push_back(bvh.nodes[1]); });
    CHECK(has_problem(problems, "1 nodes are never reached"));
  }
  SECTION("an empty child anywhere but in a root that is one leaf") {
    const auto problems = problems_after([](Bvh& bvh) {
      bvh.nodes[0].first[1] = -1;
      bvh.nodes[0].count[1] = 0;
      bvh.nodes[0].box[1] = Aabb{};
    });
    CHECK(has_problem(problems, "node 0 child 1 is node -1"));
  }
  SECTION("stats that disagree with the tree") {
    CHECK(has_problem(problems_after([](Bvh& bvh) { ++bvh.stats.nodes; }), "stats.nodes"));
    CHECK(has_problem(problems_after([](Bvh& bvh) { ++bvh.stats.leaves; }), "stats.leaves"));
    CHECK(has_problem(problems_after([](Bvh& bvh) { ++bvh.stats.depth; }), "stats.depth"));
    CHECK(has_problem(problems_after([](Bvh& bvh) { ++bvh.stats.leaf_sizes[1]; }),
                      "stats.leaf_sizes"));
    CHECK(has_problem(problems_after([](Bvh& bvh) { bvh.stats.sah_cost *= 1.001; }),
                      "stats.sah_cost"));
    CHECK(has_problem(problems_after([](Bvh& bvh) { bvh.stats.bytes_per_triangle += 1; }),
                      "stats.bytes_per_triangle"));
  }
  SECTION("options outside their range") {
    const auto problems = problems_after([](Bvh& bvh) { bvh.options.max_leaf_size = 0; });
    CHECK(has_problem(problems, "options: --leaf-size 0"));
  }
  SECTION("a tree checked against another mesh") {
    ch04::Mesh moved = mesh;
    moved.vertices[mesh.triangles[7].v2].z += 1.0f;
    CHECK(has_problem(check_bvh(good, moved), "differs from mesh triangle 7"));
    moved.triangles.pop_back();
    CHECK(has_problem(check_bvh(good, moved), "triangle copies for 999 mesh triangles"));
  }
}

TEST_CASE("check_bvh rejects a hand-made chain one level deeper than the bound", "[ch07]") {
  // Node i holds triangle i as its leaf child 0 and node i + 1 as child 1, down to node 64,
  // whose children are the last two triangles: a correct depth-first layout, except that its
  // deepest node sits at depth 64. Each chain is built from the bottom up, so that a child 1
  // box can be the union of everything below it.
  const auto chain = [](int node_count) {
    const int triangle_count = node_count + 1;
    ch04::Mesh mesh;
    for (int i = 0; i < triangle_count; ++i) {
      const auto x = static_cast<float>(i);
      add_triangle(mesh, {x, 0, 0}, {x + 0.5f, 0, 0}, {x, 1, 0});
    }
    Bvh bvh;
    bvh.options = options_of(SplitMethod::sah, 1);
    for (int i = 0; i < triangle_count; ++i) {
      bvh.triangles.push_back(mesh.triangle(i));
      bvh.triangle_ids.push_back(i);
      bvh.bounds.grow(bounds_of(mesh.triangle(i)));
    }
    bvh.nodes.resize(node_count);
    Aabb below = bounds_of(mesh.triangle(triangle_count - 1)); // triangles i + 1 .. the last
    for (int i = node_count - 1; i >= 0; --i) {
      BvhNode& node = bvh.nodes[i];
      node.box[0] = bounds_of(mesh.triangle(i));
      node.first[0] = i;
      node.count[0] = 1;
      node.box[1] = below;
      node.first[1] = i + 1; // the next node, or in the last node the last triangle
      node.count[1] = i == node_count - 1 ? 1 : 0;
      below.grow(node.box[0]);
    }
    bvh.stats.nodes = node_count;
    bvh.stats.leaves = triangle_count;
    bvh.stats.depth = node_count - 1;
    bvh.stats.leaf_sizes = {0, triangle_count};
    bvh.stats.sah_cost = sah_cost(bvh);
    bvh.stats.bytes_per_triangle =
        (node_count * 64.0 + triangle_count * (sizeof(TriangleF) + sizeof(int))) /
        triangle_count;
    return std::pair{bvh, mesh};
  };

  const auto [too_deep, mesh] = chain(k_max_bvh_depth + 1);
  const std::vector<std::string> problems = check_bvh(too_deep, mesh);
  INFO(all_lines(problems));
  REQUIRE(problems.size() == 1);
  CHECK(problems[0] == "node 64 is at depth 64, deeper than 63");

  // One node fewer is a valid tree: the checker objects to the depth and to nothing else.
  const auto [at_bound, smaller_mesh] = chain(k_max_bvh_depth);
  const std::vector<std::string> none = check_bvh(at_bound, smaller_mesh);
  INFO(all_lines(none));
  CHECK(none.empty());
  CHECK(at_bound.stats.depth == k_deepest);
}

TEST_CASE("degenerate inputs terminate with bounded leaves and depth", "[ch07]") {
  SECTION("10 000 copies of one triangle") {
    ch04::Mesh mesh;
    mesh.vertices = {{1, 2, 3}, {4, 2, 3}, {1, 6, 3}};
    mesh.triangles.assign(10000, {0, 1, 2});
    require_every_build_valid(mesh);
  }
  SECTION("10 000 different triangles with one centroid") {
    // Each box is [-a, a] x [-b, b] x [-c, c]: its centroid is exactly 0, its size random.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> size(1e-3f, 1.0f), unit(-1.0f, 1.0f);
    ch04::Mesh mesh;
    for (int i = 0; i < 10000; ++i) {
      const float a = size(rng), b = size(rng), c = size(rng);
      add_triangle(mesh, {-a, -b, -c}, {a, b, c},
                   {a * unit(rng), b * unit(rng), c * unit(rng)});
    }
    for (int i = 0; i < 10000; ++i) {
      const Aabb box = bounds_of(mesh.triangle(i));
      REQUIRE(0.5f * box.lo + 0.5f * box.hi == Vec3f{0, 0, 0});
    }
    require_every_build_valid(mesh);
    // With nothing to separate, the SAH falls back to halving: the median tree's shape.
    for (const int leaf : {1, 4}) {
      const Bvh sah = build_bvh(mesh, options_of(SplitMethod::sah, leaf));
      const Bvh median = build_bvh(mesh, options_of(SplitMethod::median, leaf));
      CHECK(sah.stats.depth == halving_levels(10000, leaf) - 1);
      CHECK(sah.stats.leaf_sizes == median.stats.leaf_sizes);
    }
  }
  SECTION("every triangle in the plane x = 0") {
    ch04::Mesh mesh = log_sized_soup(5000, 21);
    for (Vec3f& p : mesh.vertices) p.x = 0.0f;
    require_every_build_valid(mesh);
  }
  SECTION("zero-area triangles: repeated and collinear vertices") {
    ch04::Mesh mesh = log_sized_soup(4000, 22);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      ch04::IndexedTriangle& t = mesh.triangles[i];
      if (i % 2 == 0) {
        t.v2 = t.v0; // a repeated vertex
      } else {
        const Vec3f a = mesh.vertices[t.v0], b = mesh.vertices[t.v1];
        mesh.vertices[t.v2] = a + 0.25f * (b - a); // on the segment, up to rounding
      }
    }
    require_every_build_valid(mesh);
  }
  SECTION("every vertex at one point") {
    ch04::Mesh mesh;
    mesh.vertices = {{0.5f, -2.0f, 7.0f}};
    mesh.triangles.assign(10000, {0, 0, 0});
    require_every_build_valid(mesh);
    const Bvh bvh = build_bvh(mesh, options_of(SplitMethod::sah, 4));
    CHECK(bvh.stats.depth == halving_levels(10000, 4) - 1);
    CHECK(std::isfinite(bvh.stats.sah_cost));
  }
}

TEST_CASE("a mesh of one triangle is a root with one leaf and one empty child", "[ch07]") {
  ch04::Mesh mesh;
  add_triangle(mesh, {1, 2, 3}, {-4, 5, 6}, {7, -8, 9});
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    const Bvh bvh = build_bvh(mesh, options_of(method, 1));
    require_valid(bvh, mesh);
    REQUIRE(bvh.nodes.size() == 1);
    const BvhNode& root = bvh.nodes[0];
    CHECK(root.count[0] == 1);
    CHECK(root.first[0] == 0);
    CHECK(root.box[0].lo == Vec3f{-4, -8, 3});
    CHECK(root.box[0].hi == Vec3f{7, 5, 9});
    CHECK(root.count[1] == 0);
    CHECK(root.first[1] == -1);
    CHECK(root.box[1].empty());
    CHECK(root.box[1].lo.x == std::numeric_limits<float>::infinity());
    CHECK(root.box[1].hi.x == -std::numeric_limits<float>::infinity());
    CHECK(bvh.bounds.lo == root.box[0].lo);
    CHECK(bvh.bounds.hi == root.box[0].hi);
    CHECK(bvh.stats.nodes == 1);
    CHECK(bvh.stats.leaves == 1);
    CHECK(bvh.stats.depth == 0);
    CHECK(bvh.stats.sah_cost == 2.0); // the root visited, then one triangle tested
  }
}

TEST_CASE("two triangles: split when it pays or when a leaf cannot hold both", "[ch07]") {
  ch04::Mesh apart;
  add_triangle(apart, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  add_triangle(apart, {100, 0, 0}, {101, 0, 0}, {100, 1, 0});
  ch04::Mesh overlapping; // centroids 0.005 apart: a plane separates them, to no profit
  add_triangle(overlapping, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  add_triangle(overlapping, {0, 0, 0}, {1.01f, 0, 0}, {0, 1, 0});

  const Bvh forced = build_bvh(overlapping, options_of(SplitMethod::sah, 1));
  require_valid(forced, overlapping);
  CHECK(forced.stats.nodes == 1);
  CHECK(forced.stats.leaves == 2);

  const Bvh median = build_bvh(apart, options_of(SplitMethod::median, 4));
  require_valid(median, apart);
  CHECK(median.nodes[0].count[0] == 2); // the median never splits what fits a leaf

  const Bvh worth_it = build_bvh(apart, options_of(SplitMethod::sah, 4));
  require_valid(worth_it, apart);
  CHECK(worth_it.stats.leaf_sizes == std::vector<long long>{0, 2, 0, 0, 0});
  CHECK(worth_it.stats.sah_cost < 2.0);

  const Bvh not_worth_it = build_bvh(overlapping, options_of(SplitMethod::sah, 4));
  require_valid(not_worth_it, overlapping);
  CHECK(not_worth_it.stats.leaf_sizes == std::vector<long long>{0, 0, 1, 0, 0});
  CHECK(not_worth_it.nodes[0].first[1] == -1);
}

TEST_CASE("a mesh without triangles gives a tree without nodes", "[ch07]") {
  ch04::Mesh mesh;
  mesh.vertices = {{1, 2, 3}}; // a vertex no triangle uses does not count
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    const Bvh bvh = build_bvh(mesh, options_of(method, 4));
    CHECK(check_bvh(bvh, mesh).empty());
    CHECK(bvh.nodes.empty());
    CHECK(bvh.triangles.empty());
    CHECK(bvh.triangle_ids.empty());
    CHECK(bvh.view().node_count == 0);
    CHECK(bvh.bounds.empty());
    CHECK(bvh.stats.nodes == 0);
    CHECK(bvh.stats.leaves == 0);
    CHECK(bvh.stats.sah_cost == 0.0);
    CHECK(bvh.stats.bytes_per_triangle == 0.0);
    CHECK(sah_cost(bvh) == 0.0);
  }
}

TEST_CASE("nested triangles that pull the SAH lopsided stay within the depth bound", "[ch07]") {
  // Triangle k has legs 1.015^k from a shared corner: every triangle holds all smaller ones.
  // The SAH cuts off a few of the largest at each level. With 16 bins or more it still ends
  // near depth 45; with 2 bins it would go about 110 levels deep, and the depth rule stops it.
  ch04::Mesh mesh;
  for (int k = 0; k < 5000; ++k) {
    const auto r = static_cast<float>(std::pow(1.015, k));
    add_triangle(mesh, {0, 0, 0}, {r, 0, 0}, {0, r, 0});
  }
  for (const int leaf : {1, 4, 8}) {
    for (const int bins : {2, 16, 64}) {
      INFO("leaf size " << leaf << ", " << bins << " bins");
      const Bvh sah = build_bvh(mesh, options_of(SplitMethod::sah, leaf, bins));
      require_valid(sah, mesh);
      CHECK(sah.stats.depth <= k_deepest);
      const Bvh median = build_bvh(mesh, options_of(SplitMethod::median, leaf, bins));
      CHECK(sah.stats.depth > 2 * median.stats.depth);        // lopsided
      if (bins == 2) CHECK(sah.stats.depth >= k_deepest - 1); // as deep as the rule allows
    }
  }
}

TEST_CASE("triangles at every power of two stop at the depth bound", "[ch07]") {
  // Small triangles at x = 2^-120 .. 2^126: whatever the bin count, the last bin holds only
  // the farthest triangle, the SAH peels it off, and the tree would be a chain about 76 (16 or
  // more bins) to 148 (2 bins) levels deep. The rule lets it go as deep as it allows (62: the
  // rule keeps a level to spare) and no further.
  ch04::Mesh mesh;
  for (int e = -120; e <= 126; ++e) {
    const float x = std::ldexp(1.0f, e), leg = std::ldexp(1.0f, e - 4);
    add_triangle(mesh, {x, 0, 0}, {x + leg, 0, 0}, {x, leg, 0});
  }
  for (const int leaf : {1, 4, 8}) {
    for (const int bins : {2, 16, 64, 256}) {
      INFO("leaf size " << leaf << ", " << bins << " bins");
      const Bvh bvh = build_bvh(mesh, options_of(SplitMethod::sah, leaf, bins));
      require_valid(bvh, mesh);
      CHECK(bvh.stats.depth >= k_deepest - 1);
    }
  }
}

TEST_CASE("halving_levels counts the levels of a build that halves every node", "[ch07]") {
  CHECK(halving_levels(0, 1) == 0);
  CHECK(halving_levels(1, 1) == 0);
  CHECK(halving_levels(2, 1) == 1);
  CHECK(halving_levels(3, 1) == 2);
  CHECK(halving_levels(4, 4) == 0);
  CHECK(halving_levels(5, 4) == 1);
  CHECK(halving_levels(8, 4) == 1);
  CHECK(halving_levels(9, 4) == 2);
  CHECK(halving_levels(k_max_bvh_triangles, 1) == 28);
  CHECK(halving_levels(k_max_bvh_triangles, 64) == 22);
  // The median build halves every node: its depth is one less than the levels it needs.
  const ch04::Mesh soup = log_sized_soup(5000, 9);
  for (const int leaf : {1, 2, 3, 4, 7, 8, 64}) {
    for (const int n : {1, 2, 3, 5, 63, 64, 65, 100, 1000, 1023, 1024, 1025, 4097, 5000}) {
      INFO("leaf size " << leaf << ", " << n << " triangles");
      ch04::Mesh mesh = soup;
      mesh.triangles.resize(n);
      const Bvh bvh = build_bvh(mesh, options_of(SplitMethod::median, leaf));
      require_valid(bvh, mesh);
      CHECK(bvh.stats.depth == std::max(halving_levels(n, leaf) - 1, 0));
    }
  }
}

TEST_CASE("scaling by a power of two changes nothing, from 1e-30 to 2e38", "[ch07]") {
  // Float squares of 1e37 overflow and of 1e-30 underflow, and at 2^127 (coordinates up to
  // 2e38) even the sum of two coordinates overflows. The build must still make the same
  // decisions: the SAH only ever compares ratios of areas, the median only orders centroids.
  const ch04::Mesh mesh = log_sized_soup(3000, 13);
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    const Bvh reference = build_bvh(mesh, options_of(method, 4));
    for (const int exponent : {-100, 40, 123, 127}) {
      INFO(to_string(method) << ", scale 2^" << exponent);
      const ch04::Mesh big = scaled_by_power_of_two(mesh, exponent);
      const Bvh bvh = build_bvh(big, options_of(method, 4));
      require_valid(bvh, big);
      CHECK(bvh.triangle_ids == reference.triangle_ids);
      REQUIRE(bvh.nodes.size() == reference.nodes.size());
      for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
        for (int c = 0; c < 2; ++c) {
          CHECK(bvh.nodes[i].first[c] == reference.nodes[i].first[c]);
          CHECK(bvh.nodes[i].count[c] == reference.nodes[i].count[c]);
        }
      }
      CHECK(bvh.stats.sah_cost == Approx(reference.stats.sah_cost).epsilon(1e-12));
    }
  }
}

TEST_CASE("coordinates near the largest float and far from the origin", "[ch07]") {
  SECTION("a soup spanning -2e38 .. 2e38") {
    // (a + b + c) / 3 and (lo + hi) / 2 overflow here; the box centre 0.5 lo + 0.5 hi does
    // not, and neither do the areas, taken in double.
    const ch04::Mesh mesh = scaled_by_power_of_two(log_sized_soup(2000, 17), 127);
    require_every_build_valid(mesh);
    const Bvh sah = build_bvh(mesh, options_of(SplitMethod::sah, 4));
    const Bvh median = build_bvh(mesh, options_of(SplitMethod::median, 4));
    CHECK(std::isfinite(sah.stats.sah_cost));
    CHECK(sah.stats.sah_cost < median.stats.sah_cost);
  }
  SECTION("a soup and a sphere 1e7 from the origin") {
    // At 1e7 a float's step is 1: the small triangles collapse to lines and points.
    require_every_build_valid(translated(log_sized_soup(3000, 19), {1e7f, -1e7f, 1e7f}));
    require_every_build_valid(ch04::make_icosphere(3, {1e7, 1e7, 1e7}, 10.0));
  }
}

TEST_CASE("the SAH tree is cheaper than the median tree on a scene", "[ch07]") {
  // A finely tessellated sphere and a box on a large ground quad: the median cuts through
  // the ground's huge triangles and the sphere alike; the SAH isolates the ground.
  ch04::Mesh scene = ch04::make_icosphere(4, {0.0, 1.0, 0.0}, 1.0);
  ch04::append_mesh(scene, ch04::make_box({2.0, 0.0, 2.0}, {3.0, 1.0, 3.0}, 4));
  ch04::Mesh ground;
  ground.vertices = {{-50, 0, -50}, {50, 0, -50}, {50, 0, 50}, {-50, 0, 50}};
  ground.triangles = {{0, 2, 1}, {0, 3, 2}};
  ch04::append_mesh(scene, ground);
  for (const int leaf : {1, 4, 8}) {
    INFO("leaf size " << leaf);
    const Bvh median = build_bvh(scene, options_of(SplitMethod::median, leaf));
    const Bvh sah = build_bvh(scene, options_of(SplitMethod::sah, leaf));
    require_valid(median, scene);
    require_valid(sah, scene);
    CHECK(sah.stats.sah_cost < 0.8 * median.stats.sah_cost);
    CHECK(sah_cost(sah) == sah.stats.sah_cost);
  }
}

TEST_CASE("the stats describe the tree", "[ch07]") {
  const ch04::Mesh mesh = ch04::make_icosphere(4, {1.0, 2.0, 3.0}, 2.0);
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    const BuildOptions options = options_of(method, 8, 32);
    const Bvh bvh = build_bvh(mesh, options);
    require_valid(bvh, mesh); // nodes, leaves, depth, leaf sizes and SAH cost, counted here
    CHECK(bvh.options.method == method);
    CHECK(bvh.options.max_leaf_size == 8);
    CHECK(bvh.options.bins == 32);
    CHECK(bvh.stats.nodes == static_cast<int>(bvh.nodes.size()));
    CHECK(bvh.stats.leaves == bvh.stats.nodes + 1); // a binary tree whose leaves hang off nodes
    long long in_leaves = 0;
    for (std::size_t n = 0; n < bvh.stats.leaf_sizes.size(); ++n) {
      in_leaves += static_cast<long long>(n) * bvh.stats.leaf_sizes[n];
    }
    CHECK(in_leaves == static_cast<long long>(mesh.triangles.size()));
    const double triangles = static_cast<double>(mesh.triangles.size());
    CHECK(bvh.stats.bytes_per_triangle ==
          Approx((bvh.nodes.size() * 64.0 + triangles * 40.0) / triangles));
    CHECK(bvh.stats.build_ms >= 0.0);
    Aabb bounds;
    for (int i = 0; i < static_cast<int>(mesh.triangles.size()); ++i) {
      bounds.grow(bounds_of(mesh.triangle(i)));
    }
    CHECK(bvh.bounds.lo == bounds.lo);
    CHECK(bvh.bounds.hi == bounds.hi);
    CHECK(bvh.stats.sah_cost > 1.0);
  }
}

TEST_CASE("bad options and bad triangles are input errors naming the culprit", "[ch07]") {
  const ch04::Mesh mesh = log_sized_soup(20, 1);
  CHECK(input_error_of(mesh, options_of(SplitMethod::sah, 0)) ==
        "--leaf-size 0: a leaf holds 1 to 64 triangles");
  CHECK(input_error_of(mesh, options_of(SplitMethod::median, 65)) ==
        "--leaf-size 65: a leaf holds 1 to 64 triangles");
  CHECK(input_error_of(mesh, options_of(SplitMethod::sah, 4, 1)) ==
        "--bins 1: the SAH takes 2 to 256 bins per axis");
  CHECK(input_error_of(mesh, options_of(SplitMethod::sah, 4, 257)) ==
        "--bins 257: the SAH takes 2 to 256 bins per axis");
  CHECK_NOTHROW(build_bvh(mesh, options_of(SplitMethod::sah, 64, 256)));
  CHECK_NOTHROW(build_bvh(mesh, options_of(SplitMethod::sah, 1, 2)));
  CHECK_THROWS_AS(check_build_options(options_of(SplitMethod::sah, -1)), InputError);

  for (const float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
        -std::numeric_limits<float>::infinity()}) {
    ch04::Mesh broken = mesh;
    broken.vertices[broken.triangles[7].v1].y = bad;
    const std::string message = input_error_of(broken, options_of(SplitMethod::sah, 4));
    CHECK_THAT(message, testing::starts_with("triangle 7: vertex "));
    CHECK_THAT(message, testing::contains("is not finite"));
  }

  ch04::Mesh out_of_range = mesh;
  out_of_range.triangles[3].v2 = static_cast<int>(mesh.vertices.size());
  CHECK(input_error_of(out_of_range, options_of(SplitMethod::median, 4)) ==
        "triangle 3: vertex index 60 is out of range (the mesh has 60 vertices)");
  out_of_range.triangles[3].v2 = -1;
  CHECK_THAT(input_error_of(out_of_range, options_of(SplitMethod::median, 4)),
             testing::starts_with("triangle 3: vertex index -1 is out of range"));

  // A non-finite vertex that no triangle uses is harmless.
  ch04::Mesh spare = mesh;
  spare.vertices.push_back({std::numeric_limits<float>::quiet_NaN(), 0, 0});
  const Bvh bvh = build_bvh(spare, options_of(SplitMethod::sah, 4));
  CHECK(check_bvh(bvh, spare).empty());
}

TEST_CASE("two million tiny triangles", "[ch07][slow]") {
  // Legs of 1e-4 in a unit cube: many boxes far smaller than the bins they fall in.
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), leg(-1e-4f, 1e-4f);
  ch04::Mesh mesh;
  const int count = 2'000'000;
  mesh.vertices.reserve(3 * count);
  mesh.triangles.reserve(count);
  for (int i = 0; i < count; ++i) {
    const Vec3f p{unit(rng), unit(rng), unit(rng)};
    add_triangle(mesh, p, p + Vec3f{leg(rng), leg(rng), 0}, p + Vec3f{0, leg(rng), leg(rng)});
  }
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    INFO(to_string(method));
    const Bvh bvh = build_bvh(mesh, options_of(method, 4));
    require_valid(bvh, mesh);
    CHECK(bvh.stats.depth <= k_deepest);
  }
}
