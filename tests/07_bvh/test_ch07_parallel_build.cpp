// Chapter 07 tests of the build on several threads: for 2, 3 and 8 threads the tree is the
// one-thread tree, bit for bit (nodes, triangle order, depth, node and leaf counts, leaf sizes,
// SAH cost), on meshes large enough that the threads share the top passes and build subtrees
// apart, on the inputs that force the median fallback, at the largest coordinates a float
// holds, and on meshes too small to share at all.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
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
using rt::testing::same_bits;

namespace {

// The thread counts every case is built with besides one: two (the course's machines), an odd
// count (slices of unequal length), and more threads than this machine has cores.
constexpr int k_thread_counts[] = {2, 3, 8};

// Requires the trees to be the same: every field of every node bit for bit, the triangles in
// the same leaf order, and the stats that describe the tree's shape.
void require_same_tree(const Bvh& tree, const Bvh& serial) {
  REQUIRE(tree.nodes.size() == serial.nodes.size());
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const BvhNode& a = tree.nodes[i];
    const BvhNode& b = serial.nodes[i];
    INFO("node " << i);
    for (int c = 0; c < 2; ++c) {
      INFO("child " << c);
      REQUIRE(same_bits(a.box[c], b.box[c]));
      REQUIRE(a.first[c] == b.first[c]);
      REQUIRE(a.count[c] == b.count[c]);
    }
  }
  CHECK(same_bits(tree.nodes, serial.nodes)); // padding included
  // The first difference, not the whole arrays: a message of a million numbers helps no one.
  REQUIRE(tree.triangle_ids.size() == serial.triangle_ids.size());
  const std::ptrdiff_t first_difference =
      std::mismatch(tree.triangle_ids.begin(), tree.triangle_ids.end(),
                    serial.triangle_ids.begin())
          .first -
      tree.triangle_ids.begin();
  CHECK(first_difference == std::ssize(tree.triangle_ids));
  CHECK(same_bits(tree.triangles, serial.triangles));
  CHECK(same_bits(tree.bounds, serial.bounds));
  CHECK(tree.stats.nodes == serial.stats.nodes);
  CHECK(tree.stats.leaves == serial.stats.leaves);
  CHECK(tree.stats.depth == serial.stats.depth);
  CHECK(tree.stats.leaf_sizes == serial.stats.leaf_sizes);
  CHECK(same_bits(tree.stats.sah_cost, serial.stats.sah_cost));
  CHECK(tree.stats.references == serial.stats.references);
}

// Builds `mesh` on one thread and on each of k_thread_counts, checks the serial tree, and
// requires every other to equal it.
void require_same_for_every_thread_count(const ch04::Mesh& mesh, BuildOptions options) {
  options.threads = 1;
  const Bvh serial = build_bvh(mesh, options);
  const std::vector<std::string> problems = check_bvh(serial, mesh);
  INFO((problems.empty() ? std::string("valid") : problems.front()));
  REQUIRE(problems.empty());
  for (const int threads : k_thread_counts) {
    INFO(threads << " threads, " << to_string(options.method) << ", leaves of up to "
                 << options.max_leaf_size);
    options.threads = threads;
    require_same_tree(build_bvh(mesh, options), serial);
  }
}

void require_same_for_both_methods(const ch04::Mesh& mesh, std::initializer_list<int> leaves) {
  for (const SplitMethod method : {SplitMethod::sah, SplitMethod::median})
    for (const int leaf : leaves)
      require_same_for_every_thread_count(mesh, options_of(method, leaf));
}

// Triangles of random sizes whose boxes [-a, a] x [-b, b] x [-c, c] all have the centroid 0.
ch04::Mesh one_centroid(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> size(1e-3f, 1.0f), unit(-1.0f, 1.0f);
  ch04::Mesh mesh;
  for (int i = 0; i < count; ++i) {
    const Vec3f e{size(rng), size(rng), size(rng)};
    const int first = static_cast<int>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(),
                         {-e, e, Vec3f{e.x * unit(rng), e.y * unit(rng), e.z * unit(rng)}});
    mesh.triangles.push_back({first, first + 1, first + 2});
  }
  return mesh;
}

} // namespace

TEST_CASE("a soup of 300 000 triangles builds the same tree on 1, 2, 3 and 8 threads",
          "[ch07][parallel-build]") {
  const ch04::Mesh mesh = rt::testing::random_soup(300000, 71);
  require_same_for_both_methods(mesh, {1, 4});
}

TEST_CASE("a scene of a soup, a sphere and a grid box builds the same tree on every thread "
          "count",
          "[ch07][parallel-build]") {
  // Many equal centroids on the box's grid and a lopsided SAH: the partition moves many
  // references and the subtrees differ greatly in size.
  const ch04::Mesh mesh = rt::testing::mixed_scene(120000, 72);
  require_same_for_both_methods(mesh, {4, 16});
  require_same_for_every_thread_count(mesh, options_of(SplitMethod::sah, 4, 2));
  require_same_for_every_thread_count(mesh, options_of(SplitMethod::sah, 8, 256));
}

TEST_CASE("every centroid the same: the median fallback builds the same tree on every thread "
          "count",
          "[ch07][parallel-build]") {
  const ch04::Mesh mesh = one_centroid(60000, 73);
  for (int i = 0; i < 60000; i += 997) {
    const Aabb box = bounds_of(mesh.triangle(i));
    REQUIRE(0.5f * box.lo + 0.5f * box.hi == Vec3f{0, 0, 0});
  }
  require_same_for_both_methods(mesh, {1, 4});
  const Bvh bvh = build_bvh(mesh, options_of(SplitMethod::sah, 4));
  CHECK(bvh.stats.depth == halving_levels(60000, 4) - 1);
}

TEST_CASE("copies of one triangle build the same tree on every thread count",
          "[ch07][parallel-build]") {
  ch04::Mesh mesh;
  mesh.vertices = {{1, 2, 3}, {4, 2, 3}, {1, 6, 3}};
  mesh.triangles.assign(50000, {0, 1, 2});
  require_same_for_both_methods(mesh, {1, 4});
}

TEST_CASE("coordinates up to 2e38 and far from the origin build the same tree on every "
          "thread count",
          "[ch07][parallel-build]") {
  SECTION("a soup spanning -2e38 .. 2e38") {
    ch04::Mesh mesh = rt::testing::random_soup(60000, 74);
    for (Vec3f& p : mesh.vertices)
      p = {std::ldexp(p.x, 125), std::ldexp(p.y, 125), std::ldexp(p.z, 125)};
    const Bvh bvh = build_bvh(mesh, options_of(SplitMethod::sah, 4));
    REQUIRE(bvh.bounds.hi.x > 1e38f);
    CHECK(std::isfinite(bvh.stats.sah_cost));
    require_same_for_both_methods(mesh, {4});
  }
  SECTION("a soup 1e7 from the origin, its small triangles collapsed to lines and points") {
    const ch04::Mesh mesh = rt::testing::random_soup(60000, 75, {1e7f, -1e7f, 1e7f}, 100.0f);
    require_same_for_both_methods(mesh, {4});
  }
}

TEST_CASE("meshes of 0, 1, 2 and a few thousand triangles build the same tree on every "
          "thread count",
          "[ch07][parallel-build]") {
  // Too small for the threads to share anything: the one-thread build, whatever is asked.
  for (const int count : {0, 1, 2, 100, 5000}) {
    INFO(count << " triangles");
    require_same_for_both_methods(rt::testing::random_soup(count, 76), {1, 4});
  }
}

TEST_CASE("the spatial-split build gives the same tree whatever threads are asked for",
          "[ch07][parallel-build]") {
  BuildOptions options = options_of(SplitMethod::sbvh, 4);
  require_same_for_every_thread_count(rt::testing::mixed_scene(8000, 77), options);
}

TEST_CASE("a thread count out of range is an input error naming it", "[ch07][parallel-build]") {
  const ch04::Mesh mesh = rt::testing::random_soup(10, 78);
  for (const int threads : {-1, k_max_build_threads + 1}) {
    BuildOptions options;
    options.threads = threads;
    INFO(threads);
    CHECK_THROWS_WITH(build_bvh(mesh, options),
                      rt::testing::contains("build threads " + std::to_string(threads)));
  }
  BuildOptions options;
  options.threads = k_max_build_threads;
  CHECK(build_bvh(mesh, options).triangle_ids.size() == 10);
}

TEST_CASE("the stats say how many threads built the tree", "[ch07][parallel-build]") {
  const ch04::Mesh large = rt::testing::random_soup(20000, 79);
  for (const int threads : {1, 2, 3}) {
    BuildOptions options;
    options.threads = threads;
    CHECK(build_bvh(large, options).stats.threads == threads);
    options.method = SplitMethod::sbvh; // spatial splits build on one thread
    CHECK(build_bvh(large, options).stats.threads == 1);
  }
  BuildOptions options;
  options.threads = 8;
  CHECK(build_bvh(rt::testing::random_soup(100, 80), options).stats.threads == 1); // too small
}
