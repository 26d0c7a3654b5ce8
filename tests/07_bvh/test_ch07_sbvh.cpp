// Chapter 07 tests of spatial splits (--split sbvh): the clipped box holds every point of the
// triangle on its side, for random and adversarial triangles (a careless float clip does not);
// every point of every triangle lies in a leaf box that references it; no ray aimed at a closed
// mesh's vertices, edges or clip corners leaks through the tree; the closest hits are brute
// force's; the SAH cost beats the object splits' on long thin triangles; the references stay
// within the budget; the checker accepts the trees and refuses a triangle twice in one leaf;
// every split shrinks both sides and the depth bound holds; the build is deterministic; bad
// options are refused.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "adversarial_rays.h"
#include "bvh_cases.h"
#include "leak_configurations.h"
#include "sbvh_cases.h"

#include "bvh_build.h"
#include "bvh_trace.h"
#include "check_bvh.h"
#include "rt/error.h"
#include "sbvh_build.h"
#include "shaded_scene.h"
#include "traverse.h"

using namespace rt;
using namespace rt::ch07;
using namespace rt::testing;
using ch04::Mesh;
using ch04::TriangleVariant;

namespace {

constexpr float k_inf = std::numeric_limits<float>::infinity();

BuildOptions sbvh_options(int max_leaf_size, double budget = 0.3, int bins = 16) {
  BuildOptions options = options_of(SplitMethod::sbvh, max_leaf_size, bins);
  options.split_budget = budget;
  return options;
}

std::string problems_of(const Bvh& bvh, const Mesh& mesh) {
  std::string text;
  for (const std::string& line : check_bvh(bvh, mesh)) text += line + "\n";
  return text;
}

// The points of the triangles no leaf box covers. A leaf that references a triangle must hold,
// with its siblings that reference it too, all of it: each point of each triangle, in double,
// must lie in some leaf box that references the triangle. Tried: the triangle's corners, the
// points where its edges cross a face of one of those boxes (where a careless clip ends short)
// and random points.
long long uncovered_points(const Bvh& bvh, const Mesh& mesh, unsigned seed) {
  std::vector<std::vector<Aabb>> boxes(mesh.triangles.size());
  for (const BvhNode& node : bvh.nodes)
    for (int c = 0; c < 2; ++c)
      for (int k = node.first[c]; k < node.first[c] + node.count[c]; ++k)
        boxes[bvh.triangle_ids[k]].push_back(node.box[c]);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long long uncovered = 0;
  for (std::size_t id = 0; id < boxes.size(); ++id) {
    const TriangleF t = mesh.triangle(static_cast<int>(id));
    const Vec3d v[3] = {t.v0.as<double>(), t.v1.as<double>(), t.v2.as<double>()};
    std::vector<Vec3d> points(v, v + 3);
    for (const Aabb& box : boxes[id])
      for (int axis = 0; axis < 3; ++axis)
        for (const double plane : {double(box.lo[axis]), double(box.hi[axis])})
          for (int e = 0; e < 3; ++e) {
            const Vec3d a = v[e], b = v[(e + 1) % 3];
            if ((a[axis] < plane && plane < b[axis]) || (b[axis] < plane && plane < a[axis]))
              points.push_back(a + (b - a) * ((plane - a[axis]) / (b[axis] - a[axis])));
          }
    for (int k = 0; k < 32; ++k) {
      double a = unit(rng), b = unit(rng);
      if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
      points.push_back(v[0] + (v[1] - v[0]) * a + (v[2] - v[0]) * b);
    }
    for (const Vec3d& p : points) {
      bool covered = false;
      for (const Aabb& box : boxes[id]) {
        bool in = true;
        for (int c = 0; c < 3; ++c) // a point a double rounding off the edge still counts
          in = in && double(box.lo[c]) <= p[c] + 1e-15 * std::abs(p[c]) &&
               p[c] - 1e-15 * std::abs(p[c]) <= double(box.hi[c]);
        covered = covered || in;
      }
      uncovered += !covered;
    }
  }
  return uncovered;
}

// The triangles below node `i`, each once and sorted. They are exactly the node's references:
// a triangle is in a node at most once, and every copy below comes from one of them. Counts in
// `not_shrinking` the interior nodes with a child that holds as many references as they do.
std::vector<int> triangles_of_node(const Bvh& bvh, int i, int& not_shrinking);

std::vector<int> triangles_of_child(const Bvh& bvh, int i, int c, int& not_shrinking) {
  const BvhNode& node = bvh.nodes[i];
  if (node.count[c] == 0)
    return node.first[c] >= 0 ? triangles_of_node(bvh, node.first[c], not_shrinking)
                              : std::vector<int>{}; // the empty child of a one-leaf root
  std::vector<int> ids(bvh.triangle_ids.begin() + node.first[c],
                       bvh.triangle_ids.begin() + node.first[c] + node.count[c]);
  std::sort(ids.begin(), ids.end());
  return ids;
}

std::vector<int> triangles_of_node(const Bvh& bvh, int i, int& not_shrinking) {
  const std::vector<int> left = triangles_of_child(bvh, i, 0, not_shrinking);
  const std::vector<int> right = triangles_of_child(bvh, i, 1, not_shrinking);
  std::vector<int> all;
  std::set_union(left.begin(), left.end(), right.begin(), right.end(), std::back_inserter(all));
  if (!right.empty() && (left.size() >= all.size() || right.size() >= all.size()))
    ++not_shrinking;
  return all;
}

int nodes_not_shrinking(const Bvh& bvh) {
  int not_shrinking = 0;
  if (!bvh.nodes.empty()) triangles_of_node(bvh, 0, not_shrinking);
  return not_shrinking;
}

// ---------------------------------------------------------------------------------------------
// The clip.

bool inside(const Aabb& box, const Vec3d& p) {
  for (int c = 0; c < 3; ++c)
    if (!(static_cast<double>(box.lo[c]) <= p[c] && p[c] <= static_cast<double>(box.hi[c])))
      return false;
  return true;
}

// The clip as one might first write it: the crossing points in float, rounded to nearest.
Aabb careless_clip(const TriangleF& t, int axis, float lo, float hi) {
  const Vec3f v[3] = {t.v0, t.v1, t.v2};
  Aabb box;
  for (int i = 0; i < 3; ++i) {
    const Vec3f a = v[i], b = v[(i + 1) % 3];
    if (a[axis] >= lo && a[axis] <= hi) box.grow(a);
    for (const float plane : {lo, hi}) {
      if ((a[axis] < plane && plane < b[axis]) || (b[axis] < plane && plane < a[axis])) {
        const float s = (plane - a[axis]) / (b[axis] - a[axis]);
        box.grow(a + (b - a) * s);
      }
    }
  }
  return box;
}

// Points of the triangle, in double (within 1e-16 of the triangle, far below a float's ulp):
// where its edges cross the slab's planes (the extreme points of the clipped part), points on
// the segments between two crossings, and random points of the triangle; those in the slab are
// checked against the box. Returns how many were outside it.
int points_outside(const TriangleF& t, int axis, float lo, float hi, const Aabb& box,
                   std::mt19937& rng) {
  const Vec3d v[3] = {t.v0.as<double>(), t.v1.as<double>(), t.v2.as<double>()};
  std::vector<Vec3d> points;
  std::vector<Vec3d> crossings;
  for (int i = 0; i < 3; ++i) {
    const Vec3d a = v[i], b = v[(i + 1) % 3];
    points.push_back(a);
    for (const double plane : {static_cast<double>(lo), static_cast<double>(hi)}) {
      if ((a[axis] < plane && plane < b[axis]) || (b[axis] < plane && plane < a[axis])) {
        const double s = (plane - a[axis]) / (b[axis] - a[axis]);
        const Vec3d q = a + (b - a) * s;
        double p_of[3];
        for (int c = 0; c < 3; ++c) // the true point lies on the edge
          p_of[c] =
              c == axis ? plane : std::clamp(q[c], std::min(a[c], b[c]), std::max(a[c], b[c]));
        const Vec3d p{p_of[0], p_of[1], p_of[2]};
        crossings.push_back(p);
        points.push_back(p);
      }
    }
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < crossings.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      for (int k = 0; k < 8; ++k)
        points.push_back(crossings[i] + (crossings[j] - crossings[i]) * unit(rng));
  for (int k = 0; k < 64; ++k) {
    double a = unit(rng), b = unit(rng);
    if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
    points.push_back(v[0] + (v[1] - v[0]) * a + (v[2] - v[0]) * b);
  }
  int outside = 0;
  for (const Vec3d& p : points) {
    if (!(p[axis] >= lo && p[axis] <= hi)) continue;
    outside += !inside(box, p);
  }
  return outside;
}

struct ClipCase {
  TriangleF triangle;
  int axis;
  float lo, hi;
};

// Random triangles, long thin slivers, coordinates near 1e6, slabs through vertices, and
// axis-aligned edges lying on a slab's plane.
std::vector<ClipCase> clip_cases(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_int_distribution<int> pick_axis(0, 2);
  std::vector<ClipCase> cases;
  for (int i = 0; i < 20000; ++i) {
    const int kind = i % 5;
    const float scale = (i % 3 == 0) ? 1e6f : (i % 3 == 1 ? 1.0f : 3e3f);
    const Vec3f centre = (i % 2 == 0) ? Vec3f{unit(rng), unit(rng), unit(rng)} * scale
                                      : Vec3f{scale, -scale, scale};
    const auto random_point = [&](float size) {
      return centre + Vec3f{unit(rng), unit(rng), unit(rng)} * size;
    };
    TriangleF t;
    if (kind == 0) { // a random triangle
      t = {random_point(scale), random_point(scale), random_point(scale)};
    } else if (kind == 1) { // a long thin sliver
      const Vec3f p = random_point(scale), q = random_point(scale);
      t = {p, q,
           0.5f * p + 0.5f * q + Vec3f{unit(rng), unit(rng), unit(rng)} * (1e-5f * scale)};
    } else { // an edge along an axis
      const Vec3f p = random_point(scale);
      const int along = pick_axis(rng);
      float q_of[3] = {p.x, p.y, p.z};
      q_of[along] = p[along] + scale * (0.5f + unit(rng));
      const Vec3f q{q_of[0], q_of[1], q_of[2]};
      t = {p, q, random_point(scale)};
    }
    const int axis = pick_axis(rng);
    const Aabb box = bounds_of(t);
    float lo, hi;
    if (kind == 3) { // the slab's planes through the edge's coordinate: the edge lies on them
      lo = t.v0[axis];
      hi = std::min(box.hi[axis], t.v0[axis] + 0.25f * (box.hi[axis] - box.lo[axis]));
      if (kind == 3 && (i & 8)) std::swap(lo, hi), lo = box.lo[axis], hi = t.v0[axis];
    } else if (kind == 4) { // a half space ending at a vertex
      lo = (i & 16) ? -k_inf : t.v2[axis];
      hi = (i & 16) ? t.v2[axis] : k_inf;
    } else {
      const float a = box.lo[axis] + (box.hi[axis] - box.lo[axis]) * (0.5f + 0.5f * unit(rng));
      const float b = box.lo[axis] + (box.hi[axis] - box.lo[axis]) * (0.5f + 0.5f * unit(rng));
      lo = std::min(a, b);
      hi = (i % 7 == 0) ? k_inf : std::max(a, b);
    }
    cases.push_back({t, axis, lo, hi});
  }
  return cases;
}

} // namespace

TEST_CASE("sbvh: the clipped box holds every point of the triangle in the slab",
          "[ch07][sbvh]") {
  std::mt19937 rng(7);
  int outside = 0, careless_outside = 0, checked = 0;
  for (const ClipCase& c : clip_cases(2009)) {
    const Aabb box = clipped_bounds(c.triangle, c.axis, c.lo, c.hi);
    // Never beyond the slab on its axis, and never beyond the triangle's own box.
    if (!box.empty()) {
      CHECK(box.lo[c.axis] >= c.lo);
      CHECK(box.hi[c.axis] <= c.hi);
      CHECK(bounds_of(c.triangle).contains(box));
    }
    outside += points_outside(c.triangle, c.axis, c.lo, c.hi, box, rng);
    careless_outside += points_outside(c.triangle, c.axis, c.lo, c.hi,
                                       careless_clip(c.triangle, c.axis, c.lo, c.hi), rng);
    ++checked;
  }
  CAPTURE(checked, careless_outside);
  CHECK(outside == 0);
  CHECK(careless_outside > 0); // the test sees the leak it guards against
  // A triangle wholly outside the slab clips to nothing; one wholly inside to its own box.
  const TriangleF t{{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  CHECK(clipped_bounds(t, 0, 2.0f, 3.0f).empty());
  CHECK(same_bits(clipped_bounds(t, 0, -1.0f, 1.0f), bounds_of(t)));
  // Clipped at x = 0.5: the crossing of the long edges is exact here.
  const Aabb half = clipped_bounds(t, 0, 0.5f, k_inf);
  CHECK(half.lo.x == 0.5f);
  CHECK(half.hi.x == 1.0f);
  CHECK(half.hi.y >= 0.5f); // rounded outward, by a hair
  CHECK(half.hi.y < 0.5f + 1e-6f);
}

TEST_CASE("sbvh: no ray aimed at vertices and edges leaks through the tree", "[ch07][sbvh]") {
  for (const auto& configuration : ch04::k_leak_configurations) {
    const Mesh mesh = configuration.make_mesh();
    for (const int bins : {3, 6, 16}) {
      for (const int leaf : {1, 4}) {
        const Bvh bvh = build_bvh(mesh, sbvh_options(leaf, 4.0, bins));
        CAPTURE(configuration.name, bins, leaf);
        REQUIRE(problems_of(bvh, mesh).empty());
        const std::vector<RayF> rays = ch04::rays_at_vertices_and_edges(
            mesh, configuration.inside(), configuration.spread, 20000, configuration.seed);
        int leaks = 0;
        for (const RayF& ray : rays)
          leaks +=
              trace_bvh<Query::closest>(TriangleVariant::watertight, bvh.view(), ray).triangle <
              0;
        CHECK(leaks == 0);
      }
    }
  }
}

TEST_CASE("sbvh: every point of every triangle lies in a leaf box that references it",
          "[ch07][sbvh]") {
  Mesh far_slivers = long_slivers(300, 31);
  for (Vec3f& v : far_slivers.vertices) v = v + Vec3f{1e5f, -1e5f, 1e5f};
  for (const Mesh& mesh : {diagonal_tube({0.0, 0.0, 0.0}), diagonal_tube({1e5, -1e5, 1e5}),
                           long_slivers(500, 32), far_slivers, mixed_scene(300, 33)}) {
    for (const int leaf : {1, 4}) {
      const Bvh bvh = build_bvh(mesh, sbvh_options(leaf, 4.0));
      CAPTURE(mesh.triangles.size(), leaf, bvh.stats.references);
      REQUIRE(problems_of(bvh, mesh).empty());
      CHECK(bvh.stats.spatial_splits > 0);
      CHECK(uncovered_points(bvh, mesh, 41) == 0);
    }
  }
}

TEST_CASE("sbvh: no ray leaks out of a tube of long thin triangles", "[ch07][sbvh]") {
  for (const Vec3d centre : {Vec3d{0.0, 0.0, 0.0}, Vec3d{1e5, -1e5, 1e5}}) {
    const Mesh tube = diagonal_tube(centre);
    for (const int bins : {3, 8, 16}) {
      for (const int leaf : {1, 4}) {
        const Bvh bvh = build_bvh(tube, sbvh_options(leaf, 4.0, bins));
        CAPTURE(centre.x, bins, leaf, bvh.stats.spatial_splits, bvh.stats.references);
        REQUIRE(problems_of(bvh, tube).empty());
        CHECK(bvh.stats.spatial_splits > 0); // else the test would test the SAH tree
        CHECK(bvh.stats.references > static_cast<long long>(tube.triangles.size()));
        int leaks = 0;
        for (const RayF& ray :
             ch04::rays_at_vertices_and_edges(tube, centre.as<float>(), 0.3f, 20000, 77 + bins))
          leaks +=
              trace_bvh<Query::closest>(TriangleVariant::watertight, bvh.view(), ray).triangle <
              0;
        CHECK(leaks == 0);
        const std::vector<RayF> corner_rays =
            rays_at_clip_corners(bvh, centre.as<float>(), 5 + bins);
        int corner_leaks = 0;
        for (const RayF& ray : corner_rays)
          corner_leaks +=
              trace_bvh<Query::closest>(TriangleVariant::watertight, bvh.view(), ray).triangle <
              0;
        CAPTURE(corner_rays.size());
        CHECK(corner_rays.size() > 100);
        CHECK(corner_leaks == 0);
      }
    }
  }
}

TEST_CASE("sbvh: the closest hits are brute force's on random rays", "[ch07][sbvh]") {
  struct Case {
    const char* name;
    Mesh mesh;
    Vec3f centre;
    float extent;
  };
  const std::vector<Case> cases = {
      {"mixed scene", mixed_scene(400, 5), {}, 10.0f},
      {"long slivers", long_slivers(600, 6), {}, 10.0f},
      {"sphere over box", sphere_over_box(), {}, 6.0f},
      {"chapter 06's scene", ch06::make_default_scene(2, 1.0, {}).mesh, {}, 6.0f},
      {"long slivers at 1e5", long_slivers(300, 8, 10.0f), {}, 10.0f},
      {"diagonal tube", diagonal_tube({0.0, 0.0, 0.0}), {}, 12.0f}};
  for (const Case& c : cases) {
    Mesh mesh = c.mesh;
    Vec3f centre = c.centre;
    if (std::string(c.name) == "long slivers at 1e5") {
      for (Vec3f& v : mesh.vertices) v = v + Vec3f{1e5f, 1e5f, -1e5f};
      centre = {1e5f, 1e5f, -1e5f};
    }
    const ch04::MeshView view = ch04::host_view(mesh);
    for (const int leaf : {1, 4}) {
      const Bvh bvh = build_bvh(mesh, sbvh_options(leaf));
      CAPTURE(c.name, leaf);
      REQUIRE(problems_of(bvh, mesh).empty());
      int mismatches = 0, hits = 0;
      for (const RayF& ray : random_rays(3000, 11, centre, c.extent)) {
        const ch04::MeshHit brute = ch04::closest_hit(TriangleVariant::watertight, view, ray);
        const TraceHit tree =
            trace_bvh<Query::closest>(TriangleVariant::watertight, bvh.view(), ray);
        hits += brute.triangle >= 0;
        const bool same =
            brute.triangle == tree.triangle && (brute.triangle < 0 || brute.t == tree.t);
        const bool tie = brute.triangle >= 0 && tree.triangle >= 0 && brute.t == tree.t;
        mismatches += !(same || tie);
        const bool any =
            trace_bvh<Query::any>(TriangleVariant::watertight, bvh.view(), ray).triangle >= 0;
        mismatches += any != (brute.triangle >= 0);
      }
      CHECK(mismatches == 0);
      CHECK(hits > 300);
    }
  }
}

TEST_CASE("sbvh: spatial splits lower the SAH cost of long thin triangles", "[ch07][sbvh]") {
  const Mesh mesh = long_slivers(2000, 12);
  for (const int leaf : {1, 4}) {
    const Bvh sah = build_bvh(mesh, options_of(SplitMethod::sah, leaf));
    const Bvh sbvh = build_bvh(mesh, sbvh_options(leaf));
    CAPTURE(leaf, sah.stats.sah_cost, sbvh.stats.sah_cost, sbvh.stats.references);
    REQUIRE(problems_of(sbvh, mesh).empty());
    CHECK(sbvh.stats.spatial_splits > 0);
    CHECK(sbvh.stats.sah_cost < sah.stats.sah_cost);
    // With no budget nothing may be copied, and the cost is no better than a few percent
    // from the object splits' (a split with no straddler is still allowed).
    const Bvh none = build_bvh(mesh, sbvh_options(leaf, 0.0));
    REQUIRE(problems_of(none, mesh).empty());
    CHECK(none.stats.references == 2000);
    CHECK(none.stats.sah_cost > sbvh.stats.sah_cost);
  }
  // On the course's scenes spatial splits never cost more than the object splits alone.
  for (const Mesh& scene : {mixed_scene(500, 3), sphere_over_box()}) {
    const Bvh sah = build_bvh(scene, options_of(SplitMethod::sah, 4));
    const Bvh sbvh = build_bvh(scene, sbvh_options(4));
    CAPTURE(sah.stats.sah_cost, sbvh.stats.sah_cost);
    CHECK(sbvh.stats.sah_cost <= sah.stats.sah_cost * 1.0001);
  }
}

TEST_CASE("sbvh: the references stay within the budget", "[ch07][sbvh]") {
  const Mesh mesh = long_slivers(1500, 13);
  double previous = 0.0;
  for (const double budget : {0.0, 0.05, 0.3, 1.0, 4.0}) {
    const Bvh bvh = build_bvh(mesh, sbvh_options(1, budget));
    CAPTURE(budget, bvh.stats.references);
    REQUIRE(problems_of(bvh, mesh).empty());
    CHECK(bvh.stats.references == static_cast<long long>(bvh.triangle_ids.size()));
    CHECK(bvh.stats.references <= 1500 + static_cast<long long>(std::floor(budget * 1500)));
    CHECK(bvh.stats.references >= previous); // a larger budget is spent, not refused
    if (budget >= 0.3) CHECK(bvh.stats.references > 1500);
    previous = static_cast<double>(bvh.stats.references);
    // Bytes per triangle count every reference's triangle copy and id.
    const double bytes = (static_cast<double>(bvh.nodes.size()) * sizeof(BvhNode) +
                          static_cast<double>(bvh.stats.references) * (sizeof(TriangleF) + 4)) /
                         1500.0;
    CHECK(bvh.stats.bytes_per_triangle == Approx(bytes).epsilon(1e-12));
  }
}

TEST_CASE("sbvh: the checker refuses a triangle twice in one leaf", "[ch07][sbvh]") {
  const Mesh mesh = long_slivers(500, 14);
  Bvh bvh = build_bvh(mesh, sbvh_options(4, 1.0));
  REQUIRE(problems_of(bvh, mesh).empty());
  REQUIRE(bvh.stats.references > 500); // some triangle is in two leaves, and that is fine
  int node = -1, child = -1;
  for (int i = 0; i < static_cast<int>(bvh.nodes.size()) && node < 0; ++i)
    for (int c = 0; c < 2 && node < 0; ++c)
      if (bvh.nodes[i].count[c] >= 2) node = i, child = c;
  REQUIRE(node >= 0);
  const int first = bvh.nodes[node].first[child];
  bvh.triangle_ids[first + 1] = bvh.triangle_ids[first];
  bvh.triangles[first + 1] = bvh.triangles[first];
  CHECK(problems_of(bvh, mesh).find("twice") != std::string::npos);
  // The same tree labelled an SAH tree: its copies are more than its triangles.
  Bvh relabelled = build_bvh(mesh, sbvh_options(4, 1.0));
  relabelled.options.method = SplitMethod::sah;
  CHECK(problems_of(relabelled, mesh).find("triangle copies for") != std::string::npos);
}

TEST_CASE("sbvh: the depth bound holds where nothing shrinks", "[ch07][sbvh]") {
  // A thousand copies of one long triangle: every spatial split copies them all to both sides,
  // every centroid is the same. Only the median split can shrink the node.
  Mesh same;
  same.vertices = {{-5.0f, -5.0f, -5.0f}, {5.0f, 5.0f, 5.0f}, {5.0f, -5.0f, 0.0f}};
  for (int i = 0; i < 1000; ++i) same.triangles.push_back({0, 1, 2});
  // A chain of slivers, each a little longer than the last: the tree is deep.
  Mesh chain;
  for (int i = 0; i < 3000; ++i) {
    const float x = std::ldexp(1.0f, i % 40 - 20);
    const int base = static_cast<int>(chain.vertices.size());
    chain.vertices.push_back({-x, -x, 0.0f});
    chain.vertices.push_back({x, x, 1e-3f * x});
    chain.vertices.push_back({x, -x, 0.0f});
    chain.triangles.push_back({base, base + 1, base + 2});
  }
  for (const Mesh* mesh : {&same, &chain}) {
    for (const int leaf : {1, 2}) {
      const Bvh bvh = build_bvh(*mesh, sbvh_options(leaf, 4.0));
      CAPTURE(leaf, bvh.stats.depth);
      REQUIRE(problems_of(bvh, *mesh).empty());
      CHECK(bvh.stats.depth <= k_max_bvh_depth - 1);
      CHECK(nodes_not_shrinking(bvh) == 0);
      CHECK(bvh.stats.depth >=
            halving_levels(static_cast<long long>(mesh->triangles.size()), leaf) - 1);
    }
  }
}

TEST_CASE("sbvh: the same mesh and options give the same arrays", "[ch07][sbvh]") {
  const Mesh mesh = mixed_scene(800, 21);
  const Bvh a = build_bvh(mesh, sbvh_options(4));
  const Bvh b = build_bvh(mesh, sbvh_options(4));
  CHECK(same_bits(a.nodes, b.nodes));
  CHECK(same_bits(a.triangles, b.triangles));
  CHECK(same_bits(a.triangle_ids, b.triangle_ids));
  CHECK(a.stats.references == b.stats.references);
  CHECK(std::string(to_string(SplitMethod::sbvh)) == "sbvh");
}

TEST_CASE("sbvh: bad options are refused in one line", "[ch07][sbvh]") {
  const Mesh mesh = single_triangle();
  for (const double budget : {-0.1, 4.5, std::nan("")}) {
    std::string message;
    try {
      build_bvh(mesh, sbvh_options(4, budget));
    } catch (const InputError& error) {
      message = error.what();
    }
    CAPTURE(budget, message);
    CHECK(message.find("--split-budget") == 0);
    CHECK(message.find('\n') == std::string::npos);
  }
  const Bvh edge = build_bvh(mesh, sbvh_options(4, 4.0)); // the end of the range is fine
  CHECK(edge.stats.references == 1);
}
