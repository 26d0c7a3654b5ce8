// Chapter 09 tests of wide trees collapsed from chapter 07's spatial-split (sbvh) trees: every
// layout from every collapse passes the checker and gives brute force's hits on a course scene
// and on long thin triangles; a wide child's box is the binary tree's clipped box, not its
// triangles' box; a wide leaf never holds a triangle twice; no adversarial ray leaks; the
// checker names a reference removed or doubled; the report counts the references; and the
// program takes --split and --split-budget, refusing bad values in one line.
#include <algorithm>
#include <bit>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "rt_catch.h"

#include "07_bvh/program_cases.h"
#include "07_bvh/sbvh_cases.h"
#include "adversarial_rays.h"
#include "bvh_trace.h"
#include "leak_configurations.h"
#include "obj_loader.h"
#include "ray_io.h"
#include "run_program.h"
#include "wide_cases.h"
#include "wide_tracers.h"

using namespace rt;
using namespace rt::ch09;
using namespace rt::ch09::testing;
using rt::testing::diagonal_tube;
using rt::testing::long_slivers;
using rt::testing::ProgramRun;
using rt::testing::rays_at_clip_corners;

namespace {

ch07::BuildOptions sbvh_options(double budget = 0.3, int bins = 16) {
  ch07::BuildOptions options;
  options.method = ch07::SplitMethod::sbvh;
  options.split_budget = budget;
  options.bins = bins;
  return options;
}

std::string problems_of_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

template <class Node, class Triangles>
std::string problems_of(const WideTree<Node, Triangles>& tree, const Mesh& mesh,
                        const ch07::BuildOptions& options) {
  return problems_of_lines(check_wide_tree(tree, mesh, options));
}

// Every stored layout of both collapses of one sbvh tree.
struct SbvhTrees {
  WideLayout sah4, greedy4, sah8, greedy8;
  Wide4Bvh wide4_sah, wide4_greedy;
  Wide8Bvh wide8_sah, wide8_greedy;
  CompressedBvh compressed_sah, compressed_greedy;
  Wide4PackedBvh wide4_packed;
};

SbvhTrees sbvh_trees(const Mesh& mesh, const ch07::BuildOptions& options) {
  SbvhTrees t;
  t.sah4 = build_wide_layout(mesh, 4, Collapse::sah, options);
  t.greedy4 = build_wide_layout(mesh, 4, Collapse::greedy, options);
  t.sah8 = build_wide_layout(mesh, 8, Collapse::sah, options);
  t.greedy8 = build_wide_layout(mesh, 8, Collapse::greedy, options);
  t.wide4_sah = pack_wide<4>(t.sah4);
  t.wide4_greedy = pack_wide<4>(t.greedy4);
  t.wide8_sah = pack_wide<8>(t.sah8);
  t.wide8_greedy = pack_wide<8>(t.greedy8);
  t.compressed_sah = compress(t.sah8);
  t.compressed_greedy = compress(t.greedy8);
  t.wide4_packed = pack_wide<4, PackedTriangles>(t.sah4);
  return t;
}

// Calls fn(name, tree) for each stored tree of `trees`.
template <class Fn> void for_each_stored(const SbvhTrees& t, Fn fn) {
  fn("wide4 sah", t.wide4_sah);
  fn("wide4 greedy", t.wide4_greedy);
  fn("wide8 sah", t.wide8_sah);
  fn("wide8 greedy", t.wide8_greedy);
  fn("cwbvh8 sah", t.compressed_sah);
  fn("cwbvh8 greedy", t.compressed_greedy);
  fn("wide4 packed", t.wide4_packed);
}

// The leaves of a stored tree: (first record, count), read from the meta bytes.
template <class Node, class Triangles>
std::vector<std::pair<int, int>> leaves_of(const WideTree<Node, Triangles>& tree) {
  std::vector<std::pair<int, int>> leaves;
  for (const Node& node : tree.nodes)
    for (int c = 0; c < Node::k_width; ++c) {
      const std::uint8_t meta = node.meta[c];
      if (meta == 0 || is_interior_meta(meta)) continue;
      leaves.emplace_back(node.triangle_base + int(meta & 31u),
                          std::popcount(unsigned(meta) >> 5u));
    }
  return leaves;
}

// A tree's record k rewritten as mesh triangle `id`, in the tree's own record layout.
template <class Node, class Triangles>
void overwrite_record(WideTree<Node, Triangles>& tree, int k, const Mesh& mesh, int id) {
  Triangles::write(&tree.triangles[static_cast<std::size_t>(k) * Triangles::k_records],
                   mesh.triangle(id), id);
}

struct SbvhCase {
  std::string name;
  Mesh mesh;
  Vec3f centre;
  bool splits; // spatial splits certainly happen: references beyond the triangles
};

std::vector<SbvhCase> sbvh_cases() {
  Mesh far_slivers = long_slivers(400, 8);
  const Vec3f far{1e5f, 1e5f, -1e5f};
  for (Vec3f& v : far_slivers.vertices) v = v + far;
  return {{"chapter 06's scene", ch06::make_default_scene(2, 1.0, {}).mesh, {}, false},
          {"mixed scene", mixed_scene(800, 5), {}, false},
          {"long slivers", long_slivers(800, 6), {}, true},
          {"long slivers at 1e5", far_slivers, far, true},
          {"diagonal tube", diagonal_tube({0.0, 0.0, 0.0}), {}, true}};
}

// The checker on one sbvh tree and on copies of it damaged two ways: a leaf's second record
// made its first's triangle (a triangle twice in one leaf), and a triangle's only reference
// made a triangle of another leaf (a triangle in no leaf). It must pass the tree and name both.
template <class Node, class Triangles>
void check_mutations(const WideTree<Node, Triangles>& tree, const Mesh& mesh,
                     const ch07::BuildOptions& options) {
  REQUIRE(problems_of(tree, mesh, options).empty());
  // Checked as a tree of one record per triangle, its extra references are refused.
  CHECK_THAT(problems_of(tree, mesh, {}), Catch::Contains("triangle records for"));
  const auto view = tree.view();
  const int records = static_cast<int>(tree.triangles.size() / Triangles::k_records);
  std::vector<int> references(mesh.triangles.size(), 0);
  for (int k = 0; k < records; ++k) ++references[view.triangle_id(k)];
  const std::vector<std::pair<int, int>> leaves = leaves_of(tree);

  const auto pair = std::find_if(leaves.begin(), leaves.end(),
                                 [](const std::pair<int, int>& l) { return l.second >= 2; });
  REQUIRE(pair != leaves.end());
  WideTree<Node, Triangles> doubled = tree;
  overwrite_record(doubled, pair->first + 1, mesh, view.triangle_id(pair->first));
  CHECK_THAT(problems_of(doubled, mesh, options), Catch::Contains("twice"));

  int removed = -1, other = -1;
  for (const auto& [first, count] : leaves) {
    for (int k = first; k < first + count && removed < 0; ++k)
      if (references[view.triangle_id(k)] == 1) removed = k;
    if (removed < 0) continue;
    const auto in_leaf = [&](int id) {
      for (int k = first; k < first + count; ++k)
        if (view.triangle_id(k) == id) return true;
      return false;
    };
    for (int j = 0; j < records && other < 0; ++j)
      if (!in_leaf(view.triangle_id(j))) other = view.triangle_id(j);
    break;
  }
  REQUIRE(removed >= 0);
  REQUIRE(other >= 0);
  WideTree<Node, Triangles> lost = tree;
  overwrite_record(lost, removed, mesh, other);
  CHECK_THAT(problems_of(lost, mesh, options),
             Catch::Contains("mesh triangles are in no leaf"));
}

const rt::testing::HeadlessCpuProgram run_program(RT_CH09_PROGRAM);
const std::string k_room = RT_ASSETS_DIR "/cornell_room.obj.gz";

} // namespace

TEST_CASE("sbvh: every wide layout from sbvh trees gives brute force's hits", "[ch09][sbvh]") {
  for (const SbvhCase& c : sbvh_cases()) {
    const ch07::BuildOptions options = sbvh_options(1.0);
    const SbvhTrees trees = sbvh_trees(c.mesh, options);
    const long long triangles = static_cast<long long>(c.mesh.triangles.size());
    CAPTURE(c.name, trees.sah4.stats.references, trees.greedy8.stats.references);
    CHECK(trees.sah4.stats.triangles == triangles);
    if (c.splits) { // else the test would test SAH trees
      CHECK(trees.sah4.stats.references > triangles);
      CHECK(trees.greedy8.stats.references > triangles);
    }
    const std::vector<RayF> rays = rays_for(c.mesh, 3000, 11, c.centre);
    for_each_stored(trees, [&](const char* name, const auto& tree) {
      CAPTURE(name);
      REQUIRE(problems_of(tree, c.mesh, options).empty());
      const Agreement a = against_brute_force(tree.view(), c.mesh, rays);
      CHECK(a.closest_mismatches == 0);
      CHECK(a.any_mismatches == 0);
      CHECK(a.hits > 300);
    });
  }
}

TEST_CASE("sbvh: a wide child's box is the binary tree's clipped box", "[ch09][sbvh]") {
  const Mesh mesh = long_slivers(1500, 12);
  const ch07::BuildOptions options = sbvh_options(1.0);
  for (const Collapse method : {Collapse::sah, Collapse::greedy}) {
    const ch07::Bvh binary = ch07::build_bvh(mesh, binary_options(method, options));
    REQUIRE(binary.stats.spatial_splits > 0);
    std::set<std::vector<float>> binary_boxes;
    for (const ch07::BvhNode& node : binary.nodes)
      for (const Aabb& box : node.box)
        binary_boxes.insert({box.lo.x, box.lo.y, box.lo.z, box.hi.x, box.hi.y, box.hi.z});
    const Wide4Bvh wide = pack_wide<4>(collapse(binary, 4, method));
    // Every child box is one of the binary tree's, bit for bit; some leaf's box is smaller
    // than its triangle's (the clipped part), which a box made from the triangles is not.
    int foreign = 0, clipped = 0;
    for (const WideNode<4>& node : wide.nodes)
      for (int c = 0; c < 4; ++c) {
        if (node.meta[c] == 0) continue;
        const Aabb box = child_box_of(node, c);
        foreign += binary_boxes.count(
                       {box.lo.x, box.lo.y, box.lo.z, box.hi.x, box.hi.y, box.hi.z}) == 0;
        if (is_interior_meta(node.meta[c])) continue;
        const int first = node.triangle_base + int(node.meta[c] & 31u);
        for (int k = first; k < first + std::popcount(unsigned(node.meta[c]) >> 5u); ++k)
          clipped += !box.contains(ch07::bounds_of(wide.view().triangle(k)));
      }
    CAPTURE(to_string(method), foreign, clipped);
    CHECK(foreign == 0);
    CHECK(clipped > 0);
  }
}

TEST_CASE(
    "sbvh: the collapse keeps spatial splits' lower cost and holds a triangle once a leaf",
    "[ch09][sbvh]") {
  const Mesh mesh = long_slivers(2000, 13);
  const long long triangles = static_cast<long long>(mesh.triangles.size());
  for (const Collapse method : {Collapse::sah, Collapse::greedy}) {
    const WideLayout sah = build_wide_layout(mesh, 8, method);
    const WideLayout sbvh = build_wide_layout(mesh, 8, method, sbvh_options(0.3));
    CAPTURE(to_string(method), sah.stats.sah_cost, sbvh.stats.sah_cost, sbvh.stats.references);
    CHECK(sbvh.stats.sah_cost < sah.stats.sah_cost);
    CHECK(sbvh.stats.split == ch07::SplitMethod::sbvh);
    CHECK(sah.stats.references == triangles);
    CHECK(sbvh.stats.references > triangles);
    CHECK(sbvh.stats.references <= triangles + triangles * 3 / 10);
    // Bytes per triangle: nodes and every reference's record, over the mesh's triangles.
    const Wide4PackedBvh packed =
        pack_wide<4, PackedTriangles>(build_wide_layout(mesh, 4, method, sbvh_options(0.3)));
    const double bytes = double(packed.nodes.size() * sizeof(WideNode<4>) +
                                packed.triangles.size() * sizeof(packed.triangles[0])) /
                         double(triangles);
    CHECK(packed.stats.bytes_per_triangle == Approx(bytes).epsilon(1e-12));
  }
  // The SAH collapse makes leaves of several binary leaves of one reference each; two of them
  // may reference one triangle (its two parts), which the wide leaf then holds once.
  const ch07::Bvh binary =
      ch07::build_bvh(mesh, binary_options(Collapse::sah, sbvh_options(4.0)));
  const WideLayout layout = collapse(binary, 2, Collapse::sah);
  CHECK(layout.stats.references <= static_cast<long long>(binary.triangle_ids.size()));
  const CompressedBvh tree = compress(layout);
  CHECK(problems_of(tree, mesh, sbvh_options(4.0)).empty());
}

TEST_CASE("sbvh: a wide leaf made of two parts of one triangle holds it once", "[ch09][sbvh]") {
  // The binary tree a spatial split makes of two triangles: A cut at x = 1 into two leaves
  // under node 1, B a leaf beside them. The SAH collapse to two children makes node 1 one
  // wide leaf (one triangle test is cheaper than a node and two tests), which must hold A
  // once. (With room for more children it keeps the two parts apart, each in its own box.)
  Mesh mesh;
  mesh.vertices = {{0.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f},
                   {3.0f, 0.0f, 0.0f}, {4.0f, 0.0f, 0.0f}, {3.0f, 1.0f, 0.0f}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  const Aabb left{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.0f}};
  const Aabb right{{1.0f, 0.0f, 0.0f}, {2.0f, 0.5f, 0.0f}};
  const Aabb b = ch07::bounds_of(mesh.triangle(1));
  ch07::Bvh binary;
  binary.options = binary_options(Collapse::sah, sbvh_options(1.0));
  binary.nodes = {{{{{0.0f, 0.0f, 0.0f}, {2.0f, 1.0f, 0.0f}}, b}, {1, 2}, {0, 1}},
                  {{left, right}, {0, 1}, {1, 1}}};
  binary.triangles = {mesh.triangle(0), mesh.triangle(0), mesh.triangle(1)};
  binary.triangle_ids = {0, 0, 1};
  binary.bounds = {{0.0f, 0.0f, 0.0f}, {4.0f, 1.0f, 0.0f}};
  binary.stats.triangles = 2;
  const WideLayout layout = collapse(binary, 2, Collapse::sah);
  CHECK(layout.triangle_ids == std::vector<int>{0, 1});
  CHECK(layout.stats.references == 2);
  CHECK(layout.stats.leaves == 2);
  CHECK(problems_of(pack_wide<8>(layout), mesh, binary.options).empty());
  CHECK(problems_of(compress(layout), mesh, binary.options).empty());
}

TEST_CASE("sbvh: no ray aimed at vertices and edges leaks through wide trees", "[ch09][sbvh]") {
  const auto leaks_through = [](const auto& tree, const std::vector<RayF>& rays) {
    int leaks = 0;
    for (const RayF& ray : rays) leaks += trace<Query::closest>(tree.view(), ray).triangle < 0;
    return leaks;
  };
  for (const ch04::LeakConfiguration& config : ch04::k_leak_configurations) {
    const Mesh mesh = config.make_mesh();
    const std::vector<RayF> rays = ch04::rays_at_vertices_and_edges(
        mesh, config.inside(), config.spread, 20000, config.seed);
    for (const int bins : {3, 16}) {
      const ch07::BuildOptions options = sbvh_options(4.0, bins);
      const WideLayout four = build_wide_layout(mesh, 4, Collapse::sah, options);
      const WideLayout eight = build_wide_layout(mesh, 8, Collapse::sah, options);
      const Wide4PackedBvh packed = pack_wide<4, PackedTriangles>(four);
      const Wide8Bvh wide8 = pack_wide<8>(eight);
      const CompressedBvh compressed = compress(eight);
      CAPTURE(config.name, bins);
      REQUIRE(problems_of(packed, mesh, options).empty());
      REQUIRE(problems_of(wide8, mesh, options).empty());
      REQUIRE(problems_of(compressed, mesh, options).empty());
      CHECK(leaks_through(packed, rays) == 0);
      CHECK(leaks_through(wide8, rays) == 0);
      CHECK(leaks_through(compressed, rays) == 0);
    }
  }
  // A closed tube of long thin triangles, which spatial splits do cut, at the origin and 1e5
  // away: chapter 04's rays and those aimed where the clipped parts end.
  for (const Vec3d centre : {Vec3d{0.0, 0.0, 0.0}, Vec3d{1e5, -1e5, 1e5}}) {
    const Mesh tube = diagonal_tube(centre);
    const ch07::BuildOptions options = sbvh_options(4.0, 8);
    const ch07::Bvh binary = ch07::build_bvh(tube, binary_options(Collapse::sah, options));
    const WideLayout four = collapse(binary, 4, Collapse::sah);
    const WideLayout eight = collapse(binary, 8, Collapse::sah);
    REQUIRE(four.stats.references > static_cast<long long>(tube.triangles.size()));
    const Wide4PackedBvh packed = pack_wide<4, PackedTriangles>(four);
    const Wide8Bvh wide8 = pack_wide<8>(eight);
    REQUIRE(problems_of(packed, tube, options).empty());
    REQUIRE(problems_of(wide8, tube, options).empty());
    std::vector<RayF> rays =
        ch04::rays_at_vertices_and_edges(tube, centre.as<float>(), 0.3f, 20000, 79);
    const std::vector<RayF> corners = rays_at_clip_corners(binary, centre.as<float>(), 5);
    CHECK(corners.size() > 100);
    rays.insert(rays.end(), corners.begin(), corners.end());
    CAPTURE(centre.x, rays.size());
    CHECK(leaks_through(packed, rays) == 0);
    CHECK(leaks_through(wide8, rays) == 0);
  }
}

TEST_CASE("sbvh: the checker names a reference removed or doubled in a leaf", "[ch09][sbvh]") {
  const Mesh mesh = long_slivers(600, 14);
  const ch07::BuildOptions options = sbvh_options(1.0);
  const SbvhTrees trees = sbvh_trees(mesh, options);
  for_each_stored(trees, [&](const char* name, const auto& built) {
    CAPTURE(name);
    check_mutations(built, mesh, options);
  });
}

TEST_CASE("program: --split sbvh builds every tree from spatial splits", "[ch09][sbvh]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch09_sbvh");
  const std::string json = (folder / "report.json").string();
  const ProgramRun run =
      run_program("--scene " + k_room +
                  " --split sbvh --split-budget 0.5 --width 48 --height 27 --frames 1 "
                  "--reference-rays 64 --tracer wide4_packed --output '' --json " +
                  json);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, Catch::Contains("from a spatial-split (sbvh) binary tree"));
  CHECK_THAT(run.output, Catch::Contains("references up to 1.50 times the triangles"));
  CHECK_THAT(run.output, Catch::Contains("build wide4 packed from sbvh (CPU)"));
  CHECK_THAT(run.output, Catch::Contains("references per triangle"));
  CHECK_THAT(run.output, !Catch::Contains("disagree"));
  std::ifstream in(json);
  const nlohmann::json report = nlohmann::json::parse(in);
  int builds = 0;
  for (const auto& row : report.at("rows")) {
    const std::string variant = row.at("variant").get<std::string>();
    if (variant.find(", build ") == std::string::npos) continue;
    ++builds;
    const double references = row.at("metrics").at("references_per_triangle").get<double>();
    CHECK(references >= 1.0);
    CHECK(references <= 1.5);
  }
  CHECK(builds == 1);

  // A ray file through the wide4 packed tree of an sbvh tree: brute force's hits.
  const ch04::Mesh mesh = ch05::load_obj(k_room).geometry;
  const std::vector<RayF> rays = rt::testing::room_ray_fan(400);
  const std::string ray_file = (folder / "rays.bin").string();
  const std::string hit_file = (folder / "hits.bin").string();
  ch07::write_ray_file(ray_file, rays);
  const std::vector<MeshHit> hits = rt::testing::hits_from_program(
      run_program, "--scene " + k_room + " --split sbvh --tracer wide4_packed", ray_file,
      hit_file, rays.size());
  const ch07::HitAgreement a = ch07::compare_hits(
      hits, ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, rays));
  CHECK(a.mismatches == 0);
  CHECK(a.hits > 300);
}

TEST_CASE("program: bad split options give one error line", "[ch09][sbvh]") {
  const rt::testing::RefusedInput cases[] = {
      {"--split median", 2, "--split"},
      {"--split-budget 0.5", 2, "--split-budget goes with --split sbvh"},
      {"--split sah --split-budget 0.5", 2, "--split-budget goes with --split sbvh"},
      {"--split sbvh --split-budget 9", 2, "--split-budget"},
      {"--split sbvh --split-budget -1", 2, "--split-budget"},
  };
  rt::testing::check_refused(run_program, cases);
}
