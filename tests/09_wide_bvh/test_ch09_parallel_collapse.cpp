// Chapter 09 tests of the collapse and the stored layouts on several threads: for 2, 3 and 8
// threads the SAH and greedy collapses (4 and 8 wide) give the one-thread layout, every field
// of every node bit for bit, the triangles in the same order and the same stats (the SAH cost
// to the last bit), and pack_cpu, pack_wide and compress store the same bytes; on a soup large
// enough to hand subtrees to the threads, on a lopsided chain, on a spatial-split tree (its
// references), and on meshes too small to share.
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "bvh_build.h"
#include "collapse.h"
#include "cpu_tree.h"
#include "rt/error.h"
#include "wide_cases.h"

using namespace rt;
using namespace rt::ch09;
using namespace rt::ch09::testing;
using rt::testing::same_bits;

namespace {

// The thread counts every case is collapsed with besides one: two (the course's machines), an
// odd count (pieces of unequal number), and more threads than this machine has cores.
constexpr int k_thread_counts[] = {2, 3, 8};

void require_same_layout(const WideLayout& layout, const WideLayout& serial) {
  REQUIRE(layout.width == serial.width);
  REQUIRE(layout.nodes.size() == serial.nodes.size());
  for (std::size_t i = 0; i < layout.nodes.size(); ++i) {
    const SlotNode& a = layout.nodes[i];
    const SlotNode& b = serial.nodes[i];
    INFO("node " << i);
    REQUIRE(same_bits(a.box, b.box));
    for (int s = 0; s < k_slots; ++s) {
      INFO("slot " << s);
      REQUIRE(same_bits(a.child_box[s], b.child_box[s]));
      REQUIRE(a.meta[s] == b.meta[s]);
    }
    REQUIRE(a.imask == b.imask);
    REQUIRE(a.child_base == b.child_base);
    REQUIRE(a.triangle_base == b.triangle_base);
  }
  CHECK(same_bits(layout.triangles, serial.triangles));
  CHECK(layout.triangle_ids == serial.triangle_ids);
  const WideStats& s = layout.stats;
  const WideStats& t = serial.stats;
  CHECK(s.nodes == t.nodes);
  CHECK(s.leaves == t.leaves);
  CHECK(s.depth == t.depth);
  CHECK(same_bits(s.children_per_node, t.children_per_node));
  CHECK(same_bits(s.triangles_per_leaf, t.triangles_per_leaf));
  CHECK(same_bits(s.sah_cost, t.sah_cost));
  CHECK(s.split == t.split);
  CHECK(s.triangles == t.triangles);
  CHECK(s.references == t.references);
}

template <class Tree> void require_same_stored(const Tree& tree, const Tree& serial) {
  CHECK(same_bits(tree.nodes, serial.nodes)); // padding included
  CHECK(same_bits(tree.triangles, serial.triangles));
  CHECK(same_bits(tree.columns, serial.columns));
  CHECK(tree.column_stride == serial.column_stride);
}

void require_same_cpu_tree(const CpuTree& tree, const CpuTree& serial) {
  CHECK(same_bits(tree.nodes, serial.nodes));
  CHECK(same_bits(tree.columns, serial.columns));
  CHECK(tree.ids == serial.ids);
}

// `binary` collapsed on `threads` threads: the collapse takes the binary build's count.
WideLayout collapse_on(ch07::Bvh binary, int threads, int width, Collapse method) {
  binary.options.threads = threads;
  return collapse(binary, width, method);
}

// Collapses `mesh` (both methods, 4 and 8 wide, from a binary tree built with `base`) on one
// thread and on each of k_thread_counts, checks the serial trees, and requires every other
// layout and stored tree to equal the serial one.
void require_same_for_every_thread_count(const Mesh& mesh, const ch07::BuildOptions& base) {
  for (const Collapse method : {Collapse::sah, Collapse::greedy}) {
    const ch07::Bvh binary = ch07::build_bvh(mesh, binary_options(method, base));
    for (const int width : {4, 8}) {
      INFO(to_string(method) << " collapse, " << width << " wide");
      const WideLayout serial = collapse_on(binary, 1, width, method);
      REQUIRE(serial.threads == 1);
      const Wide4Bvh serial4 = width == 4 ? pack_wide<4>(serial) : Wide4Bvh{};
      const Wide8Bvh serial8 = pack_wide<8>(serial);
      const CompressedBvh serial_compressed = compress(serial);
      const CpuTree serial_cpu = pack_cpu(serial);
      const std::vector<std::string> problems = check_wide_tree(serial8, mesh, base);
      INFO((problems.empty() ? std::string("valid") : problems.front()));
      REQUIRE(problems.empty());
      for (const int threads : k_thread_counts) {
        INFO(threads << " threads");
        const WideLayout layout = collapse_on(binary, threads, width, method);
        CHECK(layout.threads == threads);
        require_same_layout(layout, serial);
        if (width == 4) require_same_stored(pack_wide<4>(layout), serial4);
        require_same_stored(pack_wide<8>(layout), serial8);
        require_same_stored(compress(layout), serial_compressed);
        require_same_cpu_tree(pack_cpu(layout), serial_cpu);
      }
    }
  }
}

// Triangles along the x axis at exponentially growing distances (x = 1.0005^i), each a tenth
// of the gap to the next: the SAH's bins are equal slices of the centroids' extent, so nearly
// every split peels a slice of triangles off the far end, and the tree is a lopsided chain.
Mesh lopsided_chain(int count) {
  Mesh mesh;
  for (int i = 0; i < count; ++i) {
    const double x = std::pow(1.0005, i);
    const auto size = static_cast<float>(0.1 * (std::pow(1.0005, i + 1) - x));
    const Vec3f at{static_cast<float>(x), 0.0f, 0.0f};
    const int first = static_cast<int>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(),
                         {at, at + Vec3f{size, 0.0f, 0.0f}, at + Vec3f{0.0f, size, size}});
    mesh.triangles.push_back({first, first + 1, first + 2});
  }
  return mesh;
}

} // namespace

TEST_CASE("a soup of 200 000 triangles collapses and stores the same on 1, 2, 3 and 8 threads",
          "[ch09][parallel-collapse]") {
  require_same_for_every_thread_count(random_soup(200000, 91), {});
}

TEST_CASE("a lopsided chain collapses and stores the same on every thread count",
          "[ch09][parallel-collapse]") {
  const Mesh mesh = lopsided_chain(40000);
  const ch07::Bvh binary = ch07::build_bvh(mesh, binary_options(Collapse::sah, {}));
  // The case is what it says: deeper than a balanced tree of 40 000 leaves (16 levels), its
  // subtrees of very different sizes.
  REQUIRE(binary.stats.depth > 20);
  require_same_for_every_thread_count(mesh, {});
}

TEST_CASE("a spatial-split tree collapses and stores the same on every thread count",
          "[ch09][parallel-collapse]") {
  const Mesh mesh = mixed_scene(40000, 92);
  ch07::BuildOptions base;
  base.method = ch07::SplitMethod::sbvh;
  const ch07::Bvh binary = ch07::build_bvh(mesh, binary_options(Collapse::sah, base));
  // Triangles split into several references, some shared by neighbouring binary leaves.
  REQUIRE(binary.stats.references > binary.stats.triangles);
  require_same_for_every_thread_count(mesh, base);
}

TEST_CASE("meshes of 0, 1, 2 and a few thousand triangles collapse the same on every thread "
          "count",
          "[ch09][parallel-collapse]") {
  // Too small for the threads to share the collapse: the one-thread layout, whatever is asked.
  for (const int count : {0, 1, 2, 5000}) {
    INFO(count << " triangles");
    require_same_for_every_thread_count(random_soup(count, 93), {});
  }
}

TEST_CASE("a binary root whose first child is a leaf beside an interior child keeps every "
          "triangle",
          "[ch09][parallel-collapse]") {
  // One triangle far to the left of four close together: the greedy collapse's binary tree
  // (leaves of up to 3) makes the lone one a leaf, child 0, and the four an interior child 1.
  // A root like that once passed for the root of a mesh that fits one leaf.
  Mesh mesh;
  const Vec3f corners[] = {{-100, 0, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  for (const Vec3f& at : corners) {
    const int first = static_cast<int>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(),
                         {at, at + Vec3f{0.5f, 0, 0}, at + Vec3f{0, 1, 0}});
    mesh.triangles.push_back({first, first + 1, first + 2});
  }
  const ch07::Bvh binary = ch07::build_bvh(mesh, binary_options(Collapse::greedy, {}));
  const ch07::BvhNode& root = binary.nodes.at(0);
  REQUIRE(root.is_leaf(0));
  REQUIRE_FALSE(root.is_leaf(1));
  REQUIRE(root.count[1] == 0);
  for (const Collapse method : {Collapse::greedy, Collapse::sah}) {
    for (const int threads : {1, 2}) {
      INFO(to_string(method) << ", " << threads << " threads");
      const WideLayout layout = collapse_on(
          method == Collapse::greedy ? binary
                                     : ch07::build_bvh(mesh, binary_options(method, {})),
          threads, 8, method);
      CHECK(layout.triangles.size() == 5);
      const std::vector<std::string> problems = check_wide_tree(pack_wide<8>(layout), mesh);
      INFO((problems.empty() ? std::string("valid") : problems.front()));
      CHECK(problems.empty());
    }
  }
}

TEST_CASE("a node too wide to compress is an input error on any thread count, not an end",
          "[ch09][parallel-collapse]") {
  // Triangles across -3e38 .. 3e38: the root's extent is beyond the compressed node's grid.
  // The error comes from whichever thread meets that node; it must reach the caller, the same.
  Mesh mesh = random_soup(3000, 94);
  const int first = static_cast<int>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), {{-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 3e38f, 0}});
  mesh.triangles.push_back({first, first + 1, first + 2});
  const ch07::Bvh binary = ch07::build_bvh(mesh, binary_options(Collapse::sah, {}));
  std::string serial_message;
  try {
    compress(collapse_on(binary, 1, 8, Collapse::sah));
  } catch (const InputError& e) {
    serial_message = e.what();
  }
  REQUIRE_THAT(serial_message, rt::testing::contains("wider than the compressed node's grid"));
  for (const int threads : k_thread_counts) {
    INFO(threads << " threads");
    const WideLayout layout = collapse_on(binary, threads, 8, Collapse::sah);
    CHECK_THROWS_WITH(compress(layout), serial_message);
  }
}
