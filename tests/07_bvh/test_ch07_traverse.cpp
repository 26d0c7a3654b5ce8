// Chapter 07 tests of the traversal on the CPU (the same RT_HD code the GPU runs): the tree
// gives the hits of brute force on random scenes and rays, for both queries, both split
// methods and both triangle tests; the slab test's hard cases (zero direction components,
// origins on slab planes, flat boxes, denormals, far origins); NaN and infinite rays stop at
// once; the stack stays within its proven bound; closed meshes do not leak through the tree;
// and chapter 06's shading traced through the tree gives chapter 06's image.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "rt_catch.h"

#include "bvh_cases.h"

#include "bvh_build.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "heat_map.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "traverse.h"

using namespace rt;
using namespace rt::ch07;
using namespace rt::testing;
using ch04::Mesh;
using ch04::TriangleVariant;

namespace {

constexpr float k_inf = std::numeric_limits<float>::infinity();

// The tree's closest hit agrees with brute force: the same triangle, or another at exactly the
// same distance (a tie, where the order of the tests decides).
struct Agreement {
  int mismatches = 0;
  int ties = 0;
  int hits = 0;
};

Agreement compare_closest(TriangleVariant variant, const Mesh& mesh, const Bvh& bvh,
                          const std::vector<RayF>& rays) {
  Agreement a;
  const ch04::MeshView view = ch04::host_view(mesh);
  for (const RayF& ray : rays) {
    const ch04::MeshHit brute = ch04::closest_hit(variant, view, ray);
    const TraceHit tree = trace_bvh<Query::closest>(variant, bvh.view(), ray);
    if (brute.triangle >= 0) ++a.hits;
    if (brute.triangle == tree.triangle && (brute.triangle < 0 || brute.t == tree.t)) continue;
    if (brute.triangle >= 0 && tree.triangle >= 0 && brute.t == tree.t) {
      ++a.ties;
      continue;
    }
    ++a.mismatches;
  }
  return a;
}

int compare_any(TriangleVariant variant, const Mesh& mesh, const Bvh& bvh,
                const std::vector<RayF>& rays) {
  const ch04::MeshView view = ch04::host_view(mesh);
  int mismatches = 0;
  for (const RayF& ray : rays) {
    const bool brute = ch04::closest_hit(variant, view, ray).triangle >= 0;
    const TraceHit any = trace_bvh<Query::any>(variant, bvh.view(), ray);
    if (brute != (any.triangle >= 0)) ++mismatches;
    // Any hit is a real hit of that triangle within the ray's interval.
    if (any.triangle >= 0) {
      const auto h = ch04::intersect_triangle(variant, ray, mesh.triangle(any.triangle));
      if (!h.hit || h.t != any.t) ++mismatches;
    }
  }
  return mismatches;
}

} // namespace

TEST_CASE("the tree gives brute force's hits on random scenes and rays", "[ch07]") {
  const Mesh scene = mixed_scene(3000, 7);
  const std::vector<RayF> rays = random_rays(4000, 11, {}, 10.0f);
  for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah}) {
    for (const int leaf : {1, 4, 8}) {
      const Bvh bvh = build_bvh(scene, options_of(method, leaf));
      for (const TriangleVariant variant :
           {TriangleVariant::moller_trumbore, TriangleVariant::watertight}) {
        CAPTURE(to_string(method), leaf, ch04::to_string(variant));
        const Agreement a = compare_closest(variant, scene, bvh, rays);
        CHECK(a.mismatches == 0);
        CHECK(a.hits > 1000); // the rays do meet the scene
        CHECK(compare_any(variant, scene, bvh, rays) == 0);
      }
    }
  }
}

// The slab test must never refuse the box of a triangle the triangle test hits before tmax:
// else the tree skips a hit brute force keeps. The hard case is a box as flat as its triangle
// (here, triangles in planes of constant z), where the box's entry and the hit are the same
// distance computed two ways, each rounded; with tmax a float step past the hit, the box's
// computed entry can lie beyond tmax without the slack of k_tmax_slack.
TEST_CASE("the slab test keeps the box of every triangle hit before tmax", "[ch07]") {
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  int hits = 0, refused = 0;
  for (int i = 0; i < 200000; ++i) {
    const float z = 100.0f + 900.0f * (unit(rng) + 1.0f);
    const TriangleF tri{
        {-1.0f + unit(rng), -1.0f, z}, {1.0f, -1.0f + unit(rng), z}, {unit(rng), 1.0f, z}};
    const RayF ray{{unit(rng), unit(rng), 0.0f},
                   {0.001f * unit(rng), 0.001f * unit(rng), 1.0f}};
    const ch04::TriangleHitF h =
        ch04::intersect_triangle(TriangleVariant::watertight, ray, tri);
    if (!h.hit) continue;
    ++hits;
    float t_enter = 0.0f;
    const float tmax = std::nextafter(h.t, k_inf);
    if (!enter_box(bounds_of(tri), make_box_ray(ray), ray.tmin, tmax, t_enter)) ++refused;
  }
  CHECK(hits > 10000);
  CHECK(refused == 0);
}

TEST_CASE("the tree visits far fewer triangles than brute force", "[ch07]") {
  const Mesh scene = random_soup(20000, 3);
  const Bvh bvh = build_bvh(scene, {});
  const std::vector<RayF> rays = random_rays(2000, 5, {}, 10.0f);
  const TraversalWork work =
      measure_work(Query::closest, TriangleVariant::watertight, bvh.view(), rays);
  CHECK(work.triangles_per_ray < 200.0); // brute force: 20 000
  CHECK(work.nodes_per_ray < 400.0);
  CHECK(work.max_stack <= bvh.stats.depth + 1);
}

TEST_CASE("far from the origin the tree still agrees with brute force", "[ch07]") {
  for (const float offset : {1e4f, 1e6f}) {
    const Vec3f centre{offset, -offset, 0.5f * offset};
    Mesh scene = random_soup(2000, 21, centre, 10.0f);
    ch04::append_mesh(scene, ch04::make_icosphere(3, centre.as<double>(), 3.0));
    const Bvh bvh = build_bvh(scene, {});
    const std::vector<RayF> rays = random_rays(3000, 23, centre, 10.0f);
    CAPTURE(offset);
    const Agreement a = compare_closest(TriangleVariant::watertight, scene, bvh, rays);
    CHECK(a.mismatches == 0);
    CHECK(a.hits > 500);
  }
}

TEST_CASE("slab test: zero direction components inside, outside and on a slab plane",
          "[ch07]") {
  const Aabb box{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
  float t = 0.0f;
  const auto enters = [&](Vec3f o, Vec3f d) {
    return enter_box(box, make_box_ray(RayF{o, d}), 0.0f, k_inf, t);
  };
  // Along +z with x and y components zero: inside the x and y slabs, outside, on the planes.
  CHECK(enters({0.5f, 0.5f, -1.0f}, {0.0f, 0.0f, 1.0f}));
  CHECK_FALSE(enters({1.5f, 0.5f, -1.0f}, {0.0f, 0.0f, 1.0f}));
  CHECK_FALSE(enters({-0.5f, 0.5f, -1.0f}, {0.0f, 0.0f, 1.0f}));
  for (const float x : {0.0f, 1.0f}) // origin exactly on a plane of the x slab: 0 * inf
    for (const float zero : {0.0f, -0.0f}) {
      CAPTURE(x, zero);
      CHECK(enters({x, 0.5f, -1.0f}, {zero, 0.0f, 1.0f}));
      CHECK(enters({x, 0.0f, -1.0f}, {zero, -0.0f, 1.0f})); // on an edge of the box
      CHECK(t == 1.0f);
    }
  // Going the other way, with -0.0 in the zero components.
  CHECK(enters({0.0f, 1.0f, 2.0f}, {-0.0f, -0.0f, -1.0f}));
  CHECK(t == 1.0f);
  // Behind the ray, and beyond tmax.
  CHECK_FALSE(enters({0.5f, 0.5f, 2.0f}, {0.0f, 0.0f, 1.0f}));
  CHECK_FALSE(enter_box(box, make_box_ray(RayF{{0.5f, 0.5f, -3.0f}, {0.0f, 0.0f, 1.0f}}), 0.0f,
                        2.0f, t));
  // Origin inside: entered at tmin.
  CHECK(enters({0.5f, 0.5f, 0.5f}, {1.0f, 2.0f, 3.0f}));
  CHECK(t == 0.0f);
}

TEST_CASE("slab test: flat boxes and denormal directions", "[ch07]") {
  float t = 0.0f;
  const Aabb flat{{0.0f, 0.0f, 2.0f}, {1.0f, 1.0f, 2.0f}}; // a square in the plane z = 2
  CHECK(enter_box(flat, make_box_ray(RayF{{0.5f, 0.5f, 0.0f}, {0.0f, 0.0f, 1.0f}}), 0.0f, k_inf,
                  t));
  CHECK(t == 2.0f);
  CHECK(enter_box(flat, make_box_ray(RayF{{0.3f, 0.2f, 5.0f}, {0.1f, 0.1f, -1.0f}}), 0.0f,
                  k_inf, t));
  // In the plane of the square, along it: the ray touches the box.
  CHECK(enter_box(flat, make_box_ray(RayF{{-1.0f, 0.5f, 2.0f}, {1.0f, 0.0f, 0.0f}}), 0.0f,
                  k_inf, t));
  CHECK_FALSE(enter_box(flat, make_box_ray(RayF{{-1.0f, 0.5f, 2.5f}, {1.0f, 0.0f, 0.0f}}), 0.0f,
                        k_inf, t));
  // A segment-thin box (zero extent in two axes) crossed head on.
  const Aabb line{{0.0f, 0.5f, 0.5f}, {1.0f, 0.5f, 0.5f}};
  CHECK(enter_box(line, make_box_ray(RayF{{0.5f, 0.5f, -1.0f}, {0.0f, 0.0f, 1.0f}}), 0.0f,
                  k_inf, t));
  // Denormal components: their reciprocals overflow to infinity, and nothing becomes NaN.
  const float tiny = std::numeric_limits<float>::denorm_min();
  const Aabb box{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
  CHECK(enter_box(box, make_box_ray(RayF{{0.5f, 0.5f, -1.0f}, {tiny, -tiny, 1.0f}}), 0.0f,
                  k_inf, t));
  CHECK(t == 1.0f);
  CHECK_FALSE(enter_box(box, make_box_ray(RayF{{1.5f, 0.5f, -1.0f}, {tiny, tiny, 1.0f}}), 0.0f,
                        k_inf, t));
}

TEST_CASE("rays along the faces of axis-aligned boxes agree with brute force", "[ch07]") {
  // Boxes made of grid squares: every node box is flat or has faces on the rays' planes.
  Mesh scene = ch04::make_box({0.0, 0.0, 0.0}, {4.0, 4.0, 4.0}, 4);
  ch04::append_mesh(scene, ch04::make_box({5.0, 0.0, 0.0}, {6.0, 4.0, 1.0}, 2));
  const Bvh bvh = build_bvh(scene, options_of(SplitMethod::sah, 2));
  std::vector<RayF> rays;
  for (int a = 0; a <= 8; ++a)
    for (int b = 0; b <= 8; ++b) {
      const float u = 0.5f * a, v = 0.5f * b;                 // on grid lines and cell centres
      rays.push_back({{u, v, -1.0f}, {0.0f, 0.0f, 1.0f}});    // head on
      rays.push_back({{u, v, 9.0f}, {-0.0f, 0.0f, -1.0f}});   // from behind, -0.0
      rays.push_back({{-1.0f, u, v}, {1.0f, 0.0f, 0.0f}});    // along x, in face planes too
      rays.push_back({{u, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}); // in the plane z = 0
      rays.push_back({{u, 4.0f, v}, {0.0f, -1.0f, 0.0f}});    // from the top face, down
    }
  for (const TriangleVariant variant :
       {TriangleVariant::moller_trumbore, TriangleVariant::watertight}) {
    CAPTURE(ch04::to_string(variant));
    const Agreement a = compare_closest(variant, scene, bvh, rays);
    CHECK(a.mismatches == 0);
    CHECK(a.hits > 200);
    CHECK(compare_any(variant, scene, bvh, rays) == 0);
  }
}

TEST_CASE("NaN and infinite rays miss at once", "[ch07]") {
  const Mesh scene = random_soup(500, 9);
  const Bvh bvh = build_bvh(scene, {});
  for (const RayF& ray : hostile_rays()) {
    for (const auto query : {Query::closest, Query::any}) {
      Counters c;
      const TraceHit hit =
          query == Query::closest
              ? trace_bvh<Query::closest>(TriangleVariant::watertight, bvh.view(), ray, c)
              : trace_bvh<Query::any>(TriangleVariant::watertight, bvh.view(), ray, c);
      CHECK(hit.triangle == -1);
      CHECK(c.nodes == 0); // not one node read
      CHECK(c.triangles == 0);
    }
  }
  // An infinite tmax is an ordinary ray.
  CHECK(traceable(RayF{{0.0f, 0.0f, -20.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, k_inf}));
}

TEST_CASE("the traversal stack stays within the depth bound on a lopsided tree", "[ch07]") {
  // Nested triangles growing geometrically: the SAH wants to peel them off one by one.
  Mesh chain;
  float s = 1e-3f;
  for (int i = 0; i < 4000; ++i, s *= 1.001f) { // 1e-3 to 0.05
    const int base = static_cast<int>(chain.vertices.size());
    chain.vertices.push_back({-s, -s, 0.001f * i});
    chain.vertices.push_back({s, -s, 0.001f * i});
    chain.vertices.push_back({0.0f, s, 0.001f * i});
    chain.triangles.push_back({base, base + 1, base + 2});
  }
  for (const int leaf : {1, 4}) {
    const Bvh bvh = build_bvh(chain, options_of(SplitMethod::sah, leaf));
    REQUIRE(bvh.stats.depth <= k_max_bvh_depth - 1);
    std::vector<RayF> rays = random_rays(2000, 4, {0.0f, 0.0f, 2.0f}, 0.2f);
    int max_stack = 0;
    for (const RayF& ray : rays) {
      Counters c;
      trace_bvh<Query::closest>(TriangleVariant::watertight, bvh.view(), ray, c);
      max_stack = std::max(max_stack, c.max_stack);
    }
    CHECK(max_stack <= bvh.stats.depth + 1);
    CHECK(max_stack <= k_max_bvh_depth);
    CHECK(compare_closest(TriangleVariant::watertight, chain, bvh, rays).mismatches == 0);
  }
}

TEST_CASE("empty and single-triangle trees", "[ch07]") {
  const Bvh empty = build_bvh(Mesh{}, {});
  CHECK(trace_bvh<Query::closest>(TriangleVariant::watertight, empty.view(),
                                  RayF{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}})
            .triangle == -1);
  const Bvh single = build_bvh(single_triangle(), {});
  const TraceHit hit = trace_bvh<Query::closest>(TriangleVariant::watertight, single.view(),
                                                 RayF{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}});
  CHECK(hit.triangle == 0);
  CHECK(hit.t == 3.0f);
  CHECK(trace_bvh<Query::closest>(TriangleVariant::watertight, single.view(),
                                  RayF{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}})
            .triangle == -1);
}

TEST_CASE("no ray leaks out of a closed mesh through the tree", "[ch07]") {
  // Chapter 04's leak test, through the tree: the watertight test keeps its promise.
  const Mesh sphere = ch04::make_icosphere(4, {0.3, -0.2, 0.1}, 1.0);
  const Bvh bvh = build_bvh(sphere, {});
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  int leaks = 0;
  for (int i = 0; i < 20000; ++i) {
    // From the centre towards vertices and edges, where rays slip between triangles.
    const Vec3f target = sphere.vertices[i % sphere.vertices.size()];
    const Vec3f o{0.3f, -0.2f, 0.1f};
    const Vec3f d = (i % 2 == 0) ? target - o : Vec3f{unit(rng), unit(rng), unit(rng)};
    if (trace_bvh<Query::closest>(TriangleVariant::watertight, bvh.view(), RayF{o, d})
            .triangle < 0)
      ++leaks;
  }
  CHECK(leaks == 0);
}

TEST_CASE("chapter 06's shading traced through the tree gives chapter 06's image", "[ch07]") {
  const auto [scene, bvh, extent, camera] = shaded_tree_case(2, {96, 54});
  for (const bool smooth : {false, true}) {
    const unsigned features = ch06::features_used(scene, smooth, true);
    const ch06::SceneView view = ch06::host_view(scene, features);
    std::vector<Rgba8> brute(extent.pixel_count()), tree(extent.pixel_count());
    std::vector<ch06::ShadedPixelRecord> brute_records(brute.size()), tree_records(tree.size());
    ch06::render_shaded(Backend::cpu, ch06::KernelKind::specialised, features, view, camera,
                        extent, brute.data(), brute_records.data());
    render_bvh_shaded(Backend::cpu, features, with_bvh(view, bvh.view()), camera, extent,
                      tree.data(), tree_records.data());
    CAPTURE(smooth);
    CHECK(count_differing_pixels(brute, tree) == 0);
    long long shadow_rays = 0;
    for (const auto& r : tree_records) shadow_rays += r.shadow_rays;
    CHECK(shadow_rays > 1000);
  }
}

TEST_CASE("the node heat map: each pixel is the colour of its camera ray's node visits",
          "[ch07]") {
  CHECK(heat_colour(0) == Rgba8{0, 0, 0, 255});
  CHECK(heat_colour(k_heat_map_max_nodes) == Rgba8{255, 255, 255, 255});
  CHECK(heat_colour(10 * k_heat_map_max_nodes) == Rgba8{255, 255, 255, 255});
  int previous_sum = -1; // brighter with every visit
  for (int nodes = 0; nodes <= k_heat_map_max_nodes; ++nodes) {
    const Rgba8 c = heat_colour(nodes);
    CHECK(c.r + c.g + c.b > previous_sum);
    previous_sum = c.r + c.g + c.b;
  }
  const auto [scene, bvh, extent, camera] = shaded_tree_case(2, {64, 36});
  std::vector<Rgba8> pixels(extent.pixel_count());
  render_node_heat_map(Backend::cpu, bvh.view(), camera, extent, pixels.data());
  int most = 0;
  for (int y = 0; y < extent.height; ++y) {
    for (int x = 0; x < extent.width; ++x) {
      Counters counters;
      trace_bvh<Query::closest, TriangleVariant::watertight>(
          bvh.view(), camera.ray_through_pixel(x, y), counters);
      CHECK(pixels[y * extent.width + x] == heat_colour(counters.nodes));
      most = std::max(most, counters.nodes);
    }
  }
  CHECK(most > 1); // some rays go deeper than the root
}
