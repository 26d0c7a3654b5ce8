// Chapter 09 tests of the traversal on the CPU (the RT_HD code the GPU runs too): every wide
// tree gives brute force's hits and chapter 07's on random scenes and rays, near and far from
// the origin; the child test decides as chapter 07's enter_box does; closed meshes do not
// leak through any tree at the origin or 1e5 away; NaN, infinite and zero-direction rays stop
// before the first node; the stack stays within its bound; the tracers pass chapter 07's
// runner; and chapter 06's shading through the compressed tree gives chapter 07's image.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "rt_catch.h"
#include "rt_skip.h"

#include "adversarial_rays.h"
#include "bvh_build.h"
#include "bvh_render.h"
#include "heat_map.h"
#include "leak_configurations.h"
#include "ray_sort.h"
#include "run_program.h"
#include "runner.h"
#include "shaded_scene.h"
#include "wide_cases.h"
#include "wide_render.h"
#include "wide_trace.h"
#include "wide_tracers.h"

using namespace rt;
using namespace rt::ch09;
using namespace rt::ch09::testing;

namespace {

// Chapter 07's tree and a wide tree agree: closest hits up to exact ties, the same occlusion.
template <class Tree>
int against_chapter07(const Tree& tree, const ch07::Bvh& bvh, const std::vector<RayF>& rays) {
  constexpr ch04::TriangleVariant k_watertight = ch04::TriangleVariant::watertight;
  int mismatches = 0;
  for (const RayF& ray : rays) {
    const TraceHit binary = ch07::trace_bvh<Query::closest, k_watertight>(bvh.view(), ray);
    const TraceHit wide = trace<Query::closest>(tree, ray);
    if (wide.t != binary.t || (wide.triangle < 0) != (binary.triangle < 0)) ++mismatches;
    const bool occluded =
        ch07::trace_bvh<Query::any, k_watertight>(bvh.view(), ray).triangle >= 0;
    if ((trace<Query::any>(tree, ray).triangle >= 0) != occluded) ++mismatches;
  }
  return mismatches;
}

// Eight boxes on a coarse grid (shared faces, flat boxes) and a ray that may lie on their
// planes, with zero and denormal direction components: the child test's stiff cases.
struct ChildCase {
  WideNode<8> node{};
  RayF ray;
};

ChildCase random_child_case(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_int_distribution<int> pick(0, 9);
  const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::denorm_min()};
  ChildCase k;
  WideNode<8>& node = k.node;
  for (int c = 0; c < 8; ++c) {
    const float a = std::round(unit(rng) * 4.0f) * 0.5f,
                b = std::round(unit(rng) * 4.0f) * 0.5f;
    node.lo_x[c] = std::min(a, b);
    node.hi_x[c] = std::max(a, b);
    node.lo_y[c] = std::round(unit(rng) * 2.0f) * 0.5f;
    node.hi_y[c] = node.lo_y[c] + std::round(std::abs(unit(rng)) * 2.0f) * 0.5f;
    node.lo_z[c] = unit(rng);
    node.hi_z[c] = node.lo_z[c] + std::abs(unit(rng));
  }
  // From a point on the coarse grid towards one of the boxes, or anywhere.
  const Vec3f o{std::round(unit(rng) * 6.0f) * 0.5f, std::round(unit(rng) * 6.0f) * 0.5f,
                unit(rng) * 3.0f};
  const int aim = pick(rng) % 8;
  const Vec3f centre{0.5f * (node.lo_x[aim] + node.hi_x[aim]),
                     0.5f * (node.lo_y[aim] + node.hi_y[aim]),
                     0.5f * (node.lo_z[aim] + node.hi_z[aim])};
  Vec3f d = pick(rng) < 7 ? centre - o : Vec3f{unit(rng), unit(rng), unit(rng)};
  if (pick(rng) < 3) d.x = special[pick(rng) % 5];
  if (pick(rng) < 3) d.y = special[pick(rng) % 5];
  if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) d.z = 1.0f;
  k.ray = RayF{o, d, 0.0f, pick(rng) < 2 ? 1.5f : k_inf};
  // Every byte is a meta byte to meta_bits, so random ones give the bits of all kinds of
  // children and empty slots.
  for (int c = 0; c < 8; ++c) node.meta[c] = static_cast<std::uint8_t>(rng());
  node.imask = static_cast<std::uint8_t>(rng());
  return k;
}

} // namespace

TEST_CASE("wide trees give brute force's and chapter 07's hits on random scenes", "[ch09]") {
  const Mesh scene = mixed_scene(3000, 7);
  const std::vector<RayF> rays = rays_for(scene, 3000, 11);
  const ch07::Bvh bvh = ch07::build_bvh(scene, {});
  const WideTrees trees = all_wide_trees(scene);
  for_each_tree(trees, [&](const char* name, const auto& view) {
    CAPTURE(name);
    const Agreement a = against_brute_force(view, scene, rays);
    CHECK(a.closest_mismatches == 0);
    CHECK(a.any_mismatches == 0);
    CHECK(a.hits > 2000); // the rays do meet the scene
    CHECK(against_chapter07(view, bvh, rays) == 0);
  });
}

TEST_CASE("far from the origin the wide trees still agree with brute force", "[ch09]") {
  for (const float offset : {1e4f, 1e5f, 1e6f}) {
    const Vec3f centre{offset, -offset, 0.5f * offset};
    const Mesh scene = mixed_scene(1500, 21, centre);
    const std::vector<RayF> rays = rays_for(scene, 2000, 23, centre);
    const WideTrees trees = all_wide_trees(scene);
    for_each_tree(trees, [&](const char* name, const auto& view) {
      CAPTURE(offset, name);
      const Agreement a = against_brute_force(view, scene, rays);
      CHECK(a.closest_mismatches == 0);
      CHECK(a.any_mismatches == 0);
      CHECK(a.hits > 500);
    });
  }
}

TEST_CASE("the child test, and the CPU's form of it, decide as chapter 07's enter_box, box by "
          "box",
          "[ch09]") {
  std::mt19937 rng(5);
  int tested = 0, entered = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const ChildCase k = random_child_case(rng);
    const WideNode<8>& node = k.node;
    const RayF& ray = k.ray;
    const WideRay r = make_wide_ray(ray);
    const unsigned mask = enter_children(slabs_of(node, r), r.box, ray.tmin, ray.tmax);
    CHECK(enter_children_cpu(node, r, ray.tmin, ray.tmax) == mask);
    // The whole node read (the scalar one: a WideRay has no lanes): the meta bits of the
    // children entered.
    std::uint32_t bits_expected = 0;
    for (int c = 0; c < 8; ++c)
      if ((mask >> c) & 1u) bits_expected |= meta_bits(node.meta[c], r.octant_inverse);
    const NodeHits h = intersect_node(node, r, ray.tmin, ray.tmax);
    CHECK(h.children == ((bits_expected & 0xff000000u) | node.imask));
    CHECK(h.triangles == (bits_expected & 0x00ffffffu));
    for (int c = 0; c < 8; ++c) {
      float t = 0.0f;
      const bool expected =
          ch07::enter_box(child_box_of(node, c), r.box, ray.tmin, ray.tmax, t);
      CAPTURE(trial, c);
      CHECK(((mask >> c) & 1u) == (expected ? 1u : 0u));
      entered += expected;
      ++tested;
    }
  }
  CHECK(tested == 32000);
  CHECK(entered > 3000); // the boxes are entered often enough to mean something
}

TEST_CASE("the CPU's AVX2 node reads give the scalar node read's hits bit for bit", "[ch09]") {
#if defined(__AVX2__)
  // intersect_node with the ray's eight lanes (node_bits_avx2) against intersect_node with
  // the WideRay alone, which has no vector code whatever the compile flags: the float nodes
  // and rays of the test above, and the same boxes in compressed nodes.
  const auto same_node_hits = [](const NodeHits& a, const NodeHits& b) {
    return a.children == b.children && a.triangles == b.triangles &&
           a.child_base == b.child_base && a.triangle_base == b.triangle_base;
  };
  std::mt19937 rng(6);
  int compared = 0, entered_float = 0, entered_compressed = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const ChildCase k = random_child_case(rng);
    const RayF& ray = k.ray;
    const WideRay r = make_wide_ray(ray);
    const WideRayAvx2 lanes{r, make_eight_lane_ray(r)};
    const NodeHits scalar = intersect_node(k.node, r, ray.tmin, ray.tmax);
    CAPTURE(trial);
    CHECK(same_node_hits(intersect_node(k.node, lanes, ray.tmin, ray.tmax), scalar));
    // The same boxes on a grid of 1/32 or 1/16 (the grid's corner below them all), each
    // plane rounded outward and then moved out by up to one more step.
    CompressedNode compressed{};
    const float corner[3] = {-2.0f, -1.0f, -1.0f};
    for (int axis = 0; axis < 3; ++axis) {
      compressed.origin[axis] = corner[axis];
      compressed.exponent[axis] = static_cast<std::uint8_t>(127 - 5 + rng() % 2);
    }
    const auto on_grid = [&](float x, int axis, bool up) {
      const float steps = (x - corner[axis]) / grid_step(compressed.exponent[axis]);
      const float q =
          up ? std::ceil(steps) + float(rng() % 2) : std::floor(steps) - float(rng() % 2);
      return static_cast<std::uint8_t>(std::clamp(q, 0.0f, 255.0f));
    };
    for (int c = 0; c < 8; ++c) {
      compressed.q_lo_x[c] = on_grid(k.node.lo_x[c], 0, false);
      compressed.q_lo_y[c] = on_grid(k.node.lo_y[c], 1, false);
      compressed.q_lo_z[c] = on_grid(k.node.lo_z[c], 2, false);
      compressed.q_hi_x[c] = on_grid(k.node.hi_x[c], 0, true);
      compressed.q_hi_y[c] = on_grid(k.node.hi_y[c], 1, true);
      compressed.q_hi_z[c] = on_grid(k.node.hi_z[c], 2, true);
      compressed.meta[c] = k.node.meta[c];
    }
    compressed.imask = k.node.imask;
    compressed.child_base = static_cast<int>(rng() % 1000);
    compressed.triangle_base = static_cast<int>(rng() % 1000);
    const NodeHits compressed_scalar = intersect_node(compressed, r, ray.tmin, ray.tmax);
    CHECK(same_node_hits(intersect_node(compressed, lanes, ray.tmin, ray.tmax),
                         compressed_scalar));
    compared += 2;
    entered_float += std::popcount(enter_children_cpu(k.node, r, ray.tmin, ray.tmax));
    entered_compressed += std::popcount(enter_children_cpu(compressed, r, ray.tmin, ray.tmax));
  }
  CHECK(compared == 8000);
  // Children entered often enough to mean something (of 32 000 each).
  CHECK(entered_float > 3000);
  CHECK(entered_compressed > 3000);
#else
  RT_SKIP("this build's CPU code has no AVX2 (RT_CPU_ARCH), so it has no vector node read");
#endif
}

TEST_CASE("no ray leaks out of a closed mesh through a wide tree", "[ch09]") {
  // Chapter 04's adversarial rays at vertices and edges, from inside closed meshes at the
  // origin and 1e5 away: the watertight test's promise must survive quantised boxes.
  for (const ch04::LeakConfiguration& config : ch04::k_leak_configurations) {
    const Mesh mesh = config.make_mesh();
    const std::vector<RayF> rays = ch04::rays_at_vertices_and_edges(
        mesh, config.inside(), config.spread, 20000, config.seed);
    const WideTrees trees = all_wide_trees(mesh);
    for_each_tree(trees, [&](const char* name, const auto& view) {
      CAPTURE(config.name, name);
      int leaks = 0;
      for (const RayF& ray : rays) leaks += trace<Query::closest>(view, ray).triangle < 0;
      CHECK(leaks == 0);
      int any_leaks = 0;
      for (const RayF& ray : rays) any_leaks += trace<Query::any>(view, ray).triangle < 0;
      CHECK(any_leaks == 0);
      // The CPU's batch path (axes fixed per ray, eight triangles at a time with AVX2).
      for (const Query query : {Query::closest, Query::any}) {
        std::vector<MeshHit> hits(rays.size());
        trace_wide_cpu(query, view, rays, hits);
        int batch_leaks = 0;
        for (const MeshHit& hit : hits) batch_leaks += hit.triangle < 0;
        CHECK(batch_leaks == 0);
      }
    });
  }
}

TEST_CASE("NaN, infinite and zero-direction rays miss before the first node read", "[ch09]") {
  const Mesh scene = mixed_scene(500, 9);
  const WideTrees trees = all_wide_trees(scene);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const RayF bad[] = {
      {{nan, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}},
      {{0.0f, 0.0f, -20.0f}, {0.0f, nan, 1.0f}},
      {{k_inf, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f}},
      {{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, -k_inf}},
      {{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 0.0f}},
      {{0.0f, 0.0f, -20.0f}, {-0.0f, -0.0f, -0.0f}},
      {{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 1.0f}, nan, k_inf},
      {{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, nan},
  };
  for_each_tree(trees, [&](const char* name, const auto& view) {
    for (const RayF& ray : bad) {
      CAPTURE(name);
      ch07::Counters closest, any;
      CHECK(trace<Query::closest>(view, ray, closest).triangle == -1);
      CHECK(trace<Query::any>(view, ray, any).triangle == -1);
      CHECK(closest.nodes + any.nodes == 0); // not one node read
      CHECK(closest.triangles + any.triangles == 0);
    }
    // An infinite tmax is an ordinary ray, and it hits.
    ch07::Counters c;
    const TraceHit hit = trace<Query::closest>(
        view, RayF{{2.0f, 0.5f, -20.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, k_inf}, c);
    CHECK(hit.triangle >= 0);
    CHECK(c.nodes > 0);
  });
}

TEST_CASE("the stack stays within its bound on a lopsided tree", "[ch09]") {
  // Triangles growing geometrically along x: as deep a tree as the depth bound allows.
  float far = 0.0f;
  const Mesh chain = geometric_chain(200, far);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_int_distribution<int> pick(0, 199);
  std::vector<RayF> rays;
  for (int i = 0; i < 2000; ++i) { // from in front of the chain at random triangles' centres
    const auto& t = chain.triangles[pick(rng)];
    const Vec3f target =
        (chain.vertices[t.v0] + chain.vertices[t.v1] + chain.vertices[t.v2]) / 3.0f;
    const Vec3f o{target.x * (1.0f + 0.1f * unit(rng)), target.x * 0.1f * unit(rng),
                  -target.x * (1.0f + unit(rng) * unit(rng))};
    rays.push_back({o, target - o});
  }
  const ch07::Bvh binary = ch07::build_bvh(chain, binary_options(Collapse::sah, {}));
  REQUIRE(binary.stats.depth > 24); // lopsided indeed: a balanced tree of 200 has depth 8
  const WideTrees trees = all_wide_trees(chain);
  const auto check = [&](const char* name, const auto& tree) {
    CAPTURE(name, tree.stats.depth);
    CHECK(tree.stats.depth <= binary.stats.depth); // a wide node is a binary node
    REQUIRE(tree.stats.depth <= k_wide_stack_size);
    const ch07::TraversalWork work = measure_wide_work(Query::closest, tree.view(), rays);
    CHECK(work.max_stack <= tree.stats.depth);
    CHECK(work.nodes_per_ray > 0.0);
    const Agreement a = against_brute_force(tree.view(), chain, rays);
    CHECK(a.closest_mismatches == 0);
    CHECK(a.any_mismatches == 0);
    CHECK(a.hits > 1500);
  };
  check("wide4 sah", trees.wide4_sah);
  check("wide4 greedy", trees.wide4_greedy);
  check("wide8 sah", trees.wide8_sah);
  check("cwbvh8 sah", trees.compressed_sah);
  check("cwbvh8 greedy", trees.compressed_greedy);
}

TEST_CASE("the batch functions give the traversal's hits on CPU threads", "[ch09]") {
  const Mesh scene = mixed_scene(1000, 13);
  const std::vector<RayF> rays = rays_for(scene, 1000, 14);
  const CompressedBvh tree = compress(build_wide_layout(scene, 8, Collapse::sah));
  // Bit for bit: the batch path (axes fixed per ray, and with AVX2 the eight-wide node read
  // and triangle test) against the one-ray traversal with chapter 04's test, on every tree.
  const WideTrees trees = all_wide_trees(scene);
  for_each_tree(trees, [&](const char* name, const auto& view) {
    for (const Query query : {Query::closest, Query::any}) {
      std::vector<MeshHit> hits(rays.size(), MeshHit{-1.0f, 12345});
      trace_wide_cpu(query, view, rays, hits);
      int differ = 0, hit = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const TraceHit one = query == Query::closest ? trace<Query::closest>(view, rays[i])
                                                     : trace<Query::any>(view, rays[i]);
        differ += hits[i].triangle != one.triangle || !(hits[i].t == one.t || one.triangle < 0);
        hit += one.triangle >= 0;
      }
      CAPTURE(name, query == Query::closest ? "closest" : "any");
      CHECK(differ == 0);
      CHECK(hit > 500);
    }
  });
  const ch07::TraversalWork closest = measure_wide_work(Query::closest, tree.view(), rays);
  const ch07::TraversalWork any = measure_wide_work(Query::any, tree.view(), rays);
  CHECK(any.nodes_per_ray <= closest.nodes_per_ray);
  CHECK(closest.triangles_per_ray < 100.0); // brute force: about 5 000
}

TEST_CASE("the CPU's eight-at-once triangle test gives chapter 04's answers bit for bit",
          "[ch09]") {
#if defined(__AVX2__) && defined(__FMA__)
  // test_triangles_avx2 (eight triangles per instruction from the tree's columns) against
  // test_triangles, the scalar loop, which has no vector code whatever the compile flags,
  // both with the axes fixed, on groups of up to 24 triangles around the one each ray hits:
  // rays at the vertices and edges of closed meshes, at the origin and 1e5 away, so that
  // neighbours tie at the same t and the rule "the first tested wins" is put to work.
  std::mt19937 rng(31);
  int compared = 0, hits = 0, ties = 0;
  for (const ch04::LeakConfiguration& config : ch04::k_leak_configurations) {
    const Mesh mesh = config.make_mesh();
    const Wide8Bvh tree = pack_wide<8>(build_wide_layout(mesh, 8, Collapse::sah));
    const auto view = tree.view();
    REQUIRE(view.columns != nullptr);
    const int count = static_cast<int>(mesh.triangles.size());
    std::vector<int> position(count); // a mesh triangle's place in the tree's order
    for (int k = 0; k < count; ++k) position[view.triangle_id(k)] = k;
    const std::vector<RayF> rays = ch04::rays_at_vertices_and_edges(
        mesh, config.inside(), config.spread, 3000, config.seed);
    for (const RayF& ray : rays) {
      const TraceHit nearest = trace<Query::closest>(view, ray);
      if (nearest.triangle < 0) continue;
      const int k = position[nearest.triangle];
      const int base = std::max(0, k - static_cast<int>(rng() % 24));
      const int span = std::min(24, count - base);
      const unsigned bits = ((static_cast<unsigned>(rng()) | (1u << (k - base))) &
                             (span == 32 ? ~0u : (1u << span) - 1u));
      const ch04::WatertightRay<float> frame = ch04::watertight_ray(ray);
      ch04::with_fixed_axes(frame, [&]<class Axes>(Axes) {
        for (const Query query : {Query::closest, Query::any}) {
          FramedWatertightTest<Axes> scalar(frame);
          RayF fast_ray = ray, scalar_ray = ray;
          TraceHit fast_hit, scalar_hit;
          ch07::NoCounters none;
          const bool fast_done = query == Query::closest
                                     ? test_triangles_avx2<Query::closest>(
                                           view, base, bits, fast_ray, fast_hit, frame, Axes{})
                                     : test_triangles_avx2<Query::any>(
                                           view, base, bits, fast_ray, fast_hit, frame, Axes{});
          const bool scalar_done =
              query == Query::closest
                  ? test_triangles<Query::closest>(view, base, bits, scalar_ray, scalar_hit,
                                                   none, scalar)
                  : test_triangles<Query::any>(view, base, bits, scalar_ray, scalar_hit, none,
                                               scalar);
          CAPTURE(config.name, base, bits);
          CHECK(fast_done == scalar_done);
          CHECK(fast_hit.triangle == scalar_hit.triangle);
          CHECK(std::memcmp(&fast_hit, &scalar_hit, sizeof fast_hit) == 0); // t, u, v too
          CHECK(std::memcmp(&fast_ray, &scalar_ray, sizeof fast_ray) == 0);
          ++compared;
          hits += scalar_hit.triangle >= 0;
        }
      });
      // Groups in which two triangles are hit at the nearest t: there the order decides.
      int at_nearest = 0;
      for (unsigned left = bits; left != 0; left &= left - 1) {
        const ch04::TriangleHitF t =
            ch04::intersect_watertight(ray, view.triangle(base + std::countr_zero(left)));
        at_nearest += t.hit && t.t == nearest.t;
      }
      ties += at_nearest >= 2;
    }
  }
  CHECK(compared > 10000);
  CHECK(hits > compared / 2);
  CHECK(ties > 50); // groups with two triangles hit at the same, nearest t (118 here)
#else
  RT_SKIP("this build's CPU code has no AVX2 and FMA (RT_CPU_ARCH), so it has no vector "
          "triangle test");
#endif
}

TEST_CASE("the runner accepts every tracer of the chapter on the CPU", "[ch09]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch09_runner");
  const std::string path = (folder / "scene.obj").string();
  {
    const Mesh scene = mixed_scene(400, 31);
    std::ofstream out(path);
    for (const Vec3f& v : scene.vertices)
      out << "v " << v.x << " " << v.y << " " << v.z << "\n";
    for (const auto& t : scene.triangles)
      out << "f " << t.v0 + 1 << " " << t.v1 + 1 << " " << t.v2 + 1 << "\n";
  }
  ch07::RunnerOptions options;
  options.extent = {48, 27};
  options.backend = Backend::cpu;
  options.frames = 1;
  options.check_rays = 256;
  options.count_work = true;
  std::vector<std::string> built;
  const auto on_build = [&](const std::string&, const std::string& tracer, const WideStats&) {
    built.push_back(tracer);
  };
  Report report("chapter 09 runner test", "Mrays/s", "chapter 07's hits");
  const ch07::SceneResult result = ch07::run_scene(
      {path}, {chapter_tracers({std::begin(k_all_tracers), std::end(k_all_tracers)}, on_build)},
      options, report);
  CHECK(result.problems == 0);
  // Every tree but the binary, once each: the traversal variants share wide4 packed's.
  CHECK(built.size() == 6);
  CHECK(std::count(built.begin(), built.end(), "wide4 packed") == 1);
  for (const ChapterTracer tracer : k_all_tracers)
    for (const ch07::RayType type :
         {ch07::RayType::primary, ch07::RayType::ao, ch07::RayType::diffuse}) {
      CAPTURE(to_string(tracer), ch07::to_string(type));
      const ch07::TracerFigure* f = result.find(to_string(tracer), type);
      REQUIRE(f != nullptr);
      CHECK(f->disagreeing == 0);
      CHECK(f->mrays > 0.0);
      CHECK(f->bytes_per_triangle > 0.0);
    }
  // The packed records hold the same 40 bytes of every triangle without the 8 of padding.
  const ch07::TracerFigure* aligned = result.find("wide4", ch07::RayType::primary);
  const ch07::TracerFigure* packed = result.find("wide4 packed", ch07::RayType::primary);
  CHECK(aligned->bytes_per_triangle - packed->bytes_per_triangle == Approx(8.0));
}

TEST_CASE("the traversal variants give wide4 packed's hits bit for bit on the CPU", "[ch09]") {
  for (const float offset : {0.0f, 1e5f}) {
    const Vec3f centre{offset, offset, -offset};
    const Mesh mesh = mixed_scene(2000, 53, centre);
    const std::vector<RayF> rays = rays_for(mesh, 3000, 54, centre);
    const ch07::Bvh bvh = ch07::build_bvh(mesh, {});
    const ch07::PinholeCamera camera =
        ch07::make_protocol_camera(centre + Vec3f{0.0f, 0.0f, 20.0f}, centre, 60.0f, 16, 9);
    const ch07::TracerScene scene{"variants", mesh, bvh, camera, Backend::cpu};
    int builds = 0;
    const std::vector<ch07::Tracer> tracers = chapter_tracers(
        {ChapterTracer::wide4_packed, ChapterTracer::wide4_packed_shared_stack,
         ChapterTracer::wide4_packed_persistent, ChapterTracer::wide4_packed_sorted,
         ChapterTracer::wide4_packed_tiles, ChapterTracer::wide4_packed_persistent_tiles},
        [&](const std::string&, const std::string&, const WideStats&) { ++builds; })(scene);
    CHECK(builds == 1); // one tree, shared
    REQUIRE(tracers.size() == 6);
    for (const Query query : {Query::closest, Query::any}) {
      std::vector<MeshHit> plain(rays.size());
      tracers[0].trace_cpu(query, rays, plain);
      CHECK(std::count_if(plain.begin(), plain.end(),
                          [](const MeshHit& h) { return h.triangle >= 0; }) > 1000);
      for (std::size_t k = 1; k < tracers.size(); ++k) {
        CAPTURE(offset, ch07::to_string(query), tracers[k].name);
        std::vector<MeshHit> variant(rays.size(), MeshHit{-1.0f, -2});
        tracers[k].trace_cpu(query, rays, variant);
        int differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i)
          differ += std::memcmp(&plain[i], &variant[i], sizeof(MeshHit)) != 0;
        CHECK(differ == 0);
        CHECK(tracers[k].bytes_per_triangle == tracers[0].bytes_per_triangle);
      }
    }
  }
}

TEST_CASE("a ray order gives each ray to one thread: an image's in tiles, a list in order",
          "[ch09]") {
  for (const auto& [width, height, count] :
       {std::tuple{13, 7, 91}, std::tuple{13, 7, 90}, std::tuple{8, 4, 32}, std::tuple{1, 1, 1},
        std::tuple{0, 0, 5}, std::tuple{640, 360, 640 * 360}}) {
    CAPTURE(width, height, count);
    const RayOrder order = RayOrder::for_image(count, width, height);
    CHECK(order.tiled() == (width * height == count && count > 0));
    std::vector<int> taken(static_cast<std::size_t>(count), 0);
    for (long long n = 0; n < order.numbers(count); ++n) {
      int i = -1;
      if (!order.ray_of(unsigned(n), count, i)) continue;
      REQUIRE((i >= 0 && i < count));
      ++taken[static_cast<std::size_t>(i)];
      if (order.tiled()) { // thread n's ray is a pixel of tile n / 32
        const int x = i % width, y = i / width, tile = int(n / 32);
        CHECK(x / 8 == tile % order.tiles.tiles_x);
        CHECK(y / 4 == tile / order.tiles.tiles_x);
      } else {
        CHECK(i == int(n));
      }
    }
    for (const int t : taken) REQUIRE(t == 1);
  }
}

TEST_CASE("rays are sorted by octant, then by their origin's Morton code", "[ch09]") {
  ch07::Aabb box;
  box.grow(Vec3f{-1.0f, -1.0f, -1.0f});
  box.grow(Vec3f{1.0f, 1.0f, 1.0f});
  const RaySortFrame frame = make_ray_sort_frame(box);
  const Vec3f low = box.lo, high = box.hi;
  const Vec3f up{0.0f, 0.0f, 1.0f}, down{0.0f, 0.0f, -1.0f};
  // The octant decides first: a ray going down sorts after every ray going up.
  CHECK(ray_sort_key({high, up}, frame) < ray_sort_key({low, down}, frame));
  CHECK(ray_sort_key({low, up}, frame) < ray_sort_key({high, up}, frame));
  CHECK(ray_sort_key({low, up}, frame) == 0u); // octant 0, cell (0, 0, 0)
  CHECK(ray_sort_key({high, {-1.0f, -1.0f, -1.0f}}, frame) == (1u << k_sort_key_bits) - 1);
  // Outside the box, and NaN, clamp to the grid's edge cells.
  CHECK(ray_sort_key({{-50.0f, -50.0f, -50.0f}, up}, frame) == 0u);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(ray_sort_key({{nan, nan, nan}, up}, frame) == 0u);
  CHECK(ray_sort_key({{50.0f, 50.0f, 50.0f}, up}, frame) == ray_sort_key({high, up}, frame));
  // Nearby origins share the key's high bits: Morton order keeps octree cells together.
  const unsigned a = ray_sort_key({{0.5f, 0.5f, 0.5f}, up}, frame);
  const unsigned b = ray_sort_key({{0.51f, 0.5f, 0.5f}, up}, frame);
  const unsigned c = ray_sort_key({{-0.5f, 0.5f, 0.5f}, up}, frame);
  CHECK((a ^ b) < (a ^ c));

  const Mesh mesh = mixed_scene(500, 57);
  const std::vector<RayF> rays = rays_for(mesh, 2000, 58);
  const std::vector<int> order = sorted_ray_order(rays, frame);
  REQUIRE(order.size() == rays.size());
  std::vector<int> seen(rays.size(), 0);
  for (const int i : order) ++seen[i];
  CHECK(std::count(seen.begin(), seen.end(), 1) == std::ssize(rays)); // a permutation
  int out_of_order = 0, moved = 0;
  for (std::size_t j = 0; j < order.size(); ++j) {
    moved += order[j] != static_cast<int>(j);
    if (j == 0) continue;
    const unsigned before = ray_sort_key(rays[order[j - 1]], frame);
    const unsigned here = ray_sort_key(rays[order[j]], frame);
    out_of_order += before > here || (before == here && order[j - 1] > order[j]);
  }
  CHECK(out_of_order == 0);
  CHECK(moved > 1000); // random rays really are reordered
}

TEST_CASE("chapter 06's shading through the compressed tree gives chapter 07's image",
          "[ch09]") {
  const ShadedView shaded;
  const auto& [scene, tree, extent, camera] = shaded;
  const ch07::Bvh bvh = ch07::build_bvh(scene.mesh, {});
  for (const bool smooth : {false, true}) {
    const unsigned features = ch06::features_used(scene, smooth, true);
    const ch06::SceneView view = ch06::host_view(scene, features);
    std::vector<Rgba8> binary(extent.pixel_count()), wide(extent.pixel_count());
    ch07::render_bvh_shaded(Backend::cpu, features, ch07::with_bvh(view, bvh.view()), camera,
                            extent, binary.data());
    render_wide_shaded(Backend::cpu, features, with_wide(view, tree.view()), camera, extent,
                       wide.data());
    CAPTURE(smooth);
    CHECK(count_differing_pixels(binary, wide) == 0);
  }
}

TEST_CASE("the wide heat map colours each ray's wide node count, and visits fewer nodes than "
          "the binary tree",
          "[ch09]") {
  const ShadedView shaded;
  const auto& [scene, tree, extent, camera] = shaded;
  const ch07::Bvh bvh = ch07::build_bvh(scene.mesh, {});
  std::vector<Rgba8> pixels(extent.pixel_count());
  render_wide_heat_map(Backend::cpu, tree.view(), camera, extent, pixels.data());
  long long wide_nodes = 0, binary_nodes = 0, differing = 0, hit_pixels = 0;
  for (int y = 0; y < extent.height; ++y)
    for (int x = 0; x < extent.width; ++x) {
      const RayF ray = camera.ray_through_pixel(x, y);
      ch07::Counters wide, binary;
      const TraceHit wide_hit = trace_wide<Query::closest>(tree.view(), ray, wide);
      ch07::trace_bvh<Query::closest, ch04::TriangleVariant::watertight>(bvh.view(), ray,
                                                                         binary);
      const Rgba8 expected = ch07::heat_colour(wide.nodes);
      const Rgba8 got = pixels[std::size_t(y) * extent.width + x];
      differing += (got.r != expected.r || got.g != expected.g || got.b != expected.b);
      wide_nodes += wide.nodes;
      binary_nodes += binary.nodes;
      hit_pixels += wide_hit.triangle >= 0;
    }
  CHECK(differing == 0);
  REQUIRE(hit_pixels > extent.pixel_count() / 10); // the model fills part of the view
  // Each wide node stands for up to seven binary ones; on this model the camera rays visit
  // fewer than half as many nodes in the wide tree.
  INFO("wide " << wide_nodes << " nodes, binary " << binary_nodes);
  CHECK(wide_nodes * 2 < binary_nodes);
  // The colour scale is chapter 07's: black for none, white at the cap and beyond.
  const Rgba8 none = ch07::heat_colour(0), full = ch07::heat_colour(ch07::k_heat_map_max_nodes);
  CHECK((none.r == 0 && none.g == 0 && none.b == 0));
  CHECK((full.r == 255 && full.g == 255 && full.b == 255));
}
