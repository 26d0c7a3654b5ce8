// Chapter 08 tests on the CPU: the packed tree holds chapter 07's tree bit for bit (boxes with
// their infinities, child links, ids, even ids whose bits are NaN floats); every tree type the
// chapter adds (16-byte records, read-only loads, the kept path) gives chapter 07's hits bit
// for bit and visits the same nodes in the same order; the memory paths' names and backends;
// the texture limit's message; and the shaded frame through the kept path is chapter 07's
// frame.
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "06_lambertian_shading/shading_cases.h"
#include "07_bvh/bvh_cases.h"
#include "memory_cases.h"

#include "bvh_build.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "kept_render.h"
#include "memory_paths.h"
#include "memory_trace.h"
#include "packed_bvh.h"
#include "rt/error.h"
#include "shaded_scene.h"
#include "texture_object.h"
#include "traverse.h"

using namespace rt;
using namespace rt::ch08;
using namespace rt::testing;
using ch04::Mesh;
using ch04::MeshHit;
using ch07::build_bvh;
using ch07::Query;
using ch07::SplitMethod;
using ch07::TraceHit;

namespace {

constexpr float k_inf = std::numeric_limits<float>::infinity();

// Random rays through mixed_scene() (some with a finite tmax or a tmin), rays aimed at
// triangles' centroids, vertices and edge midpoints (so small scenes are hit too, and rays
// meet edges and corners where the watertight test decides), rays along the grid box's faces,
// and the hostile rays that must miss at once: NaN, infinity, a zero direction.
std::vector<RayF> rays_for(const Mesh& mesh, int random_count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<RayF> rays = random_rays(rng, random_count, {}, 10.0f);
  const int aimed = std::min<int>(static_cast<int>(mesh.triangles.size()), 400);
  for (int k = 0; k < aimed; ++k) {
    const auto& t = mesh.triangles[(k * 7919) % mesh.triangles.size()];
    const Vec3f a = mesh.vertices[t.v0], b = mesh.vertices[t.v1], c = mesh.vertices[t.v2];
    const Vec3f o = Vec3f{unit(rng), unit(rng), unit(rng)} * 12.0f;
    for (const Vec3f target : {(a + b + c) / 3.0f, a, (a + b) * 0.5f})
      rays.push_back({o, target - o});
  }
  for (int a = 0; a <= 8; ++a) // along and onto the faces of the box (-4,-4,-4)..(-2,-1,3)
    for (int b = 0; b <= 8; ++b) {
      const float u = -4.0f + 0.25f * a, v = -4.0f + 0.875f * b;
      rays.push_back({{u, -1.0f, -9.0f}, {0.0f, 0.0f, 1.0f}});    // in the top face's plane
      rays.push_back({{u, v, 9.0f}, {-0.0f, -0.0f, -1.0f}});      // head on, -0.0 components
      rays.push_back({{-4.0f, u + 1.0f, v}, {0.0f, 1.0f, 0.0f}}); // in the face x = -4
      rays.push_back({{-9.0f, v * 0.375f, u}, {1.0f, 0.0f, 0.0f}});
    }
  const std::vector<RayF> hostile = hostile_rays();
  rays.insert(rays.end(), hostile.begin(), hostile.end());
  rays.push_back({{0.0f, 0.0f, -20.0f}, {-0.0f, 0.0f, -0.0f}}); // no direction, in -0.0s
  rays.push_back({{1e6f, 0.1f, 0.2f}, {-1.0f, 0.0f, 0.0f}});    // from far away
  return rays;
}

std::uint32_t bits_of(float f) { return std::bit_cast<std::uint32_t>(f); }

std::vector<MeshHit> trace_cpu(MemoryPath path, Query query, const ch07::Bvh& bvh,
                               const PackedBvh& packed, const std::vector<RayF>& rays) {
  // Poisoned: a hit not written shows up as a difference.
  std::vector<MeshHit> hits(rays.size(), MeshHit{-123.0f, 0x5a5a5a5a});
  trace_rays_path_cpu(path, query, bvh, packed, rays, hits);
  return hits;
}

template <Query kQuery, class Tree, class C = ch07::NoCounters>
TraceHit trace(const Tree& tree, const RayF& ray, C&& counters = C{}) {
  return ch07::trace_bvh<kQuery, ch04::TriangleVariant::watertight>(tree, ray, counters);
}

void check_node_equal(const BvhNode& got, const BvhNode& want) {
  for (int c = 0; c < 2; ++c) {
    CAPTURE(c);
    CHECK(bits_of(got.box[c].lo.x) == bits_of(want.box[c].lo.x));
    CHECK(bits_of(got.box[c].lo.y) == bits_of(want.box[c].lo.y));
    CHECK(bits_of(got.box[c].lo.z) == bits_of(want.box[c].lo.z));
    CHECK(bits_of(got.box[c].hi.x) == bits_of(want.box[c].hi.x));
    CHECK(bits_of(got.box[c].hi.y) == bits_of(want.box[c].hi.y));
    CHECK(bits_of(got.box[c].hi.z) == bits_of(want.box[c].hi.z));
    CHECK(got.first[c] == want.first[c]);
    CHECK(got.count[c] == want.count[c]);
  }
}

// Every node, triangle and id of `bvh` read back through the packed tree, bit for bit; the
// records' layout and spare lanes as packed_bvh.h documents them.
void check_round_trip(const ch07::Bvh& bvh) {
  const PackedBvh packed = pack_bvh(bvh);
  REQUIRE(packed.node_count == static_cast<int>(bvh.nodes.size()));
  REQUIRE(packed.nodes.size() == bvh.nodes.size() * k_node_records);
  REQUIRE(packed.triangles.size() == bvh.triangles.size() * k_triangle_records);
  const auto tree = host_view(packed);
  const KeptTree kept = host_kept_view(packed);
  CHECK(tree.node_count == packed.node_count);
  CHECK(kept.node_count == packed.node_count);
  int mismatched_nodes = 0;
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    const BvhNode n = tree.node(static_cast<int>(i));
    if (!same_bits(n, bvh.nodes[i]) || !same_bits(kept.node(static_cast<int>(i)), n)) {
      ++mismatched_nodes;
      CAPTURE(i);
      check_node_equal(n, bvh.nodes[i]);
    }
  }
  CHECK(mismatched_nodes == 0);
  int mismatched_triangles = 0;
  for (std::size_t k = 0; k < bvh.triangles.size(); ++k) {
    const int ki = static_cast<int>(k);
    const ch04::TriangleF t = tree.triangle(ki);
    const float4 v1 = packed.triangles[k_triangle_records * k + 1];
    const float4 v2 = packed.triangles[k_triangle_records * k + 2];
    const bool ok = same_bits(t, bvh.triangles[k]) && same_bits(kept.triangle(ki), t) &&
                    tree.triangle_id(ki) == bvh.triangle_ids[k] &&
                    kept.triangle_id(ki) == bvh.triangle_ids[k] && bits_of(v1.w) == 0u &&
                    bits_of(v2.w) == 0u;
    if (!ok) ++mismatched_triangles;
  }
  CHECK(mismatched_triangles == 0);
}

} // namespace

TEST_CASE("the packed tree holds chapter 07's tree bit for bit", "[ch08]") {
  SECTION("built trees, both splits, several leaf sizes") {
    const Mesh scene = mixed_scene(1500, 3);
    for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah})
      for (const int leaf : {1, 4, 8}) {
        CAPTURE(ch07::to_string(method), leaf);
        const ch07::Bvh bvh = build_bvh(scene, options_of(method, leaf));
        REQUIRE(bvh.nodes.size() > 100);
        check_round_trip(bvh);
      }
  }
  SECTION("a one-leaf tree: the empty child's infinite box and first = -1 survive") {
    Mesh few = random_soup(5, 17);
    const ch07::Bvh bvh = build_bvh(few, options_of(SplitMethod::median, 8));
    REQUIRE(bvh.nodes.size() == 1);
    REQUIRE(bvh.nodes[0].count[1] == 0);
    check_round_trip(bvh);
    const BvhNode root = host_view(pack_bvh(bvh)).node(0);
    CHECK(root.box[1].lo.x == k_inf);
    CHECK(root.box[1].lo.z == k_inf);
    CHECK(root.box[1].hi.y == -k_inf);
    CHECK(root.first[1] == -1);
    CHECK(root.count[1] == 0);
    CHECK(root.count[0] == 5);
  }
  SECTION("the records are the node's bytes in order, the id in v0's spare lane") {
    const ch07::Bvh bvh = build_bvh(mixed_scene(200, 5), {});
    const PackedBvh packed = pack_bvh(bvh);
    REQUIRE(!bvh.nodes.empty());
    const std::size_t i = bvh.nodes.size() / 2;
    const float4 r0 = packed.nodes[4 * i], r3 = packed.nodes[4 * i + 3];
    CHECK(bits_of(r0.x) == bits_of(bvh.nodes[i].box[0].lo.x));
    CHECK(bits_of(r0.w) == bits_of(bvh.nodes[i].box[0].hi.x));
    CHECK(std::bit_cast<int>(r3.x) == bvh.nodes[i].first[0]);
    CHECK(std::bit_cast<int>(r3.w) == bvh.nodes[i].count[1]);
    const std::size_t k = bvh.triangles.size() - 1;
    const float4 t0 = packed.triangles[3 * k], t2 = packed.triangles[3 * k + 2];
    CHECK(bits_of(t0.x) == bits_of(bvh.triangles[k].v0.x));
    CHECK(std::bit_cast<int>(t0.w) == bvh.triangle_ids[k]);
    CHECK(bits_of(t2.z) == bits_of(bvh.triangles[k].v2.z));
  }
  SECTION("an empty mesh packs to nothing, and every ray misses it") {
    const ch07::Bvh empty = build_bvh(Mesh{}, {});
    const PackedBvh packed = pack_bvh(empty);
    CHECK(packed.nodes.empty());
    CHECK(packed.triangles.empty());
    CHECK(packed.node_count == 0);
    const RayF ray{{0.0f, 0.0f, -5.0f}, {0.0f, 0.0f, 1.0f}};
    CHECK(trace<Query::closest>(host_view(packed), ray).triangle == -1);
    CHECK(trace<Query::any>(host_kept_view(packed), ray).triangle == -1);
    const std::vector<RayF> rays(10, ray);
    for (const MemoryPath path : {MemoryPath::global, MemoryPath::float4})
      for (const Query query : {Query::closest, Query::any}) {
        const std::vector<MeshHit> hits = trace_cpu(path, query, empty, packed, rays);
        for (const MeshHit& h : hits) {
          CHECK(h.triangle == -1);
          CHECK(h.t == k_inf);
        }
      }
  }
}

TEST_CASE("int bits ride in float lanes unchanged, NaN patterns included", "[ch08]") {
  const int tricky[] = {0,
                        1,
                        -1,
                        INT_MAX,
                        INT_MIN,
                        0x7fc00001,
                        0x7f800001, // quiet and signalling NaN with payloads
                        static_cast<int>(0xff800001u),
                        static_cast<int>(0xffc00000u),
                        0x7f800000, // +infinity
                        0x00000001, // the smallest denormal
                        123456789,
                        -987654321};
  for (const int i : tricky) {
    CAPTURE(i);
    float f;
    std::memcpy(&f, &i, sizeof f);
    CHECK(bits_as_int(f) == i);
    CHECK(std::bit_cast<int>(f) == i);
  }

  // Through pack_bvh: ids and child links patched to those patterns come back unchanged.
  const Mesh scene = random_soup(60, 23);
  ch07::Bvh bvh = build_bvh(scene, options_of(SplitMethod::sah, 2));
  REQUIRE(bvh.nodes.size() >= 4);
  const std::size_t n = std::size(tricky);
  for (std::size_t k = 0; k < bvh.triangle_ids.size(); ++k) bvh.triangle_ids[k] = tricky[k % n];
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    bvh.nodes[i].first[1] = tricky[i % n];
    bvh.nodes[i].count[0] = tricky[(i + 5) % n];
  }
  const PackedBvh packed = pack_bvh(bvh);
  const auto tree = host_view(packed);
  const KeptTree kept = host_kept_view(packed);
  for (std::size_t k = 0; k < bvh.triangle_ids.size(); ++k) {
    CAPTURE(k);
    CHECK(tree.triangle_id(static_cast<int>(k)) == bvh.triangle_ids[k]);
    CHECK(kept.triangle_id(static_cast<int>(k)) == bvh.triangle_ids[k]);
  }
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    CAPTURE(i);
    const BvhNode node = tree.node(static_cast<int>(i));
    CHECK(node.first[1] == bvh.nodes[i].first[1]);
    CHECK(node.count[0] == bvh.nodes[i].count[0]);
    CHECK(node.first[0] == bvh.nodes[i].first[0]);
    CHECK(node.count[1] == bvh.nodes[i].count[1]);
  }
}

TEST_CASE("every CPU tree type gives chapter 07's hits bit for bit", "[ch08]") {
  struct Case {
    int soup;
    unsigned seed;
    bool mixed;
  };
  const Case cases[] = {{1, 31, false}, {7, 37, false}, {300, 41, false}, {2000, 43, true}};
  for (const Case& c : cases) {
    const Mesh scene = c.mixed ? mixed_scene(c.soup, c.seed) : random_soup(c.soup, c.seed);
    const std::vector<RayF> rays = rays_for(scene, 1500, c.seed + 1);
    for (const SplitMethod method : {SplitMethod::median, SplitMethod::sah})
      for (const int leaf : {1, 8}) {
        const ch07::Bvh bvh = build_bvh(scene, options_of(method, leaf));
        const PackedBvh packed = pack_bvh(bvh);
        for (const Query query : {Query::closest, Query::any}) {
          CAPTURE(scene.triangles.size(), ch07::to_string(method), leaf,
                  ch07::to_string(query));
          // Chapter 07's own batch: the reference.
          const std::vector<MeshHit> reference = reference_hits(query, bvh, rays);
          const std::vector<MeshHit> global =
              trace_cpu(MemoryPath::global, query, bvh, packed, rays);
          const std::vector<MeshHit> records_hits =
              trace_cpu(MemoryPath::float4, query, bvh, packed, rays);
          CHECK(first_difference(global, reference) == -1);
          CHECK(first_difference(records_hits, reference) == -1);
          // The rays do meet the scene: a comparison of misses alone would prove little.
          CHECK(count_hits(reference) >= std::min<int>(200, int(scene.triangles.size())));
          // Ray by ray through every tree type, with the barycentrics too.
          const ch07::BvhView view = bvh.view();
          const ReadOnlyBvh ldg = read_only(view);
          const auto records = host_view(packed);
          const KeptTree kept = host_kept_view(packed);
          int differing = 0;
          for (const RayF& ray : rays) {
            const TraceHit want = query == Query::closest ? trace<Query::closest>(view, ray)
                                                          : trace<Query::any>(view, ray);
            const TraceHit got[] = {
                query == Query::closest ? trace<Query::closest>(ldg, ray)
                                        : trace<Query::any>(ldg, ray),
                query == Query::closest ? trace<Query::closest>(records, ray)
                                        : trace<Query::any>(records, ray),
                query == Query::closest ? trace<Query::closest>(kept, ray)
                                        : trace<Query::any>(kept, ray),
            };
            for (const TraceHit& g : got) differing += same_bits(g, want) ? 0 : 1;
          }
          CHECK(differing == 0);
        }
      }
  }
}

TEST_CASE("the packed tree is walked in chapter 07's order: same counters per ray", "[ch08]") {
  const Mesh scene = mixed_scene(2500, 53);
  const std::vector<RayF> rays = rays_for(scene, 2000, 59);
  for (const int leaf : {1, 4}) {
    const ch07::Bvh bvh = build_bvh(scene, options_of(SplitMethod::sah, leaf));
    const PackedBvh packed = pack_bvh(bvh);
    for (const Query query : {Query::closest, Query::any}) {
      CAPTURE(leaf, ch07::to_string(query));
      long long nodes = 0, triangles = 0;
      int max_stack = 0, differing = 0;
      for (const RayF& ray : rays) {
        ch07::Counters want, records, kept, ldg;
        if (query == Query::closest) {
          trace<Query::closest>(bvh.view(), ray, want);
          trace<Query::closest>(host_view(packed), ray, records);
          trace<Query::closest>(host_kept_view(packed), ray, kept);
          trace<Query::closest>(read_only(bvh.view()), ray, ldg);
        } else {
          trace<Query::any>(bvh.view(), ray, want);
          trace<Query::any>(host_view(packed), ray, records);
          trace<Query::any>(host_kept_view(packed), ray, kept);
          trace<Query::any>(read_only(bvh.view()), ray, ldg);
        }
        for (const ch07::Counters& c : {records, kept, ldg})
          if (c.nodes != want.nodes || c.triangles != want.triangles ||
              c.max_stack != want.max_stack)
            ++differing;
        nodes += want.nodes;
        triangles += want.triangles;
        max_stack = std::max(max_stack, want.max_stack);
      }
      CHECK(differing == 0);
      // The counters did count: a walk that reads nothing would agree trivially.
      CHECK(nodes > 10 * static_cast<long long>(rays.size()));
      CHECK(triangles > static_cast<long long>(rays.size()));
      CHECK(max_stack >= 2);
    }
  }
}

TEST_CASE("memory path names, lists and backends", "[ch08]") {
  SECTION("every name parses back to its path") {
    std::vector<std::string> names;
    for (const MemoryPath path : k_all_paths) {
      const std::string name = to_string(path);
      CAPTURE(name);
      CHECK(parse_memory_path(name) == path);
      CHECK(std::string(describe(path)).size() > 10);
      for (const std::string& other : names) CHECK(other != name);
      names.push_back(name);
    }
    CHECK(names ==
          std::vector<std::string>{"global", "ldg", "float4", "float4_ldg", "texture"});
  }
  SECTION("lists: all, duplicates, order") {
    const std::vector<MemoryPath> all(std::begin(k_all_paths), std::end(k_all_paths));
    CHECK(all.size() == 5);
    CHECK(parse_memory_paths("all") == all);
    CHECK(parse_memory_paths("float4,global,float4") ==
          std::vector<MemoryPath>{MemoryPath::global, MemoryPath::float4});
    CHECK(parse_memory_paths("texture") == std::vector<MemoryPath>{MemoryPath::texture});
    CHECK(parse_memory_paths("texture,float4_ldg,ldg,float4,global") == all);
  }
  SECTION("unknown names are usage errors that name the bad name") {
    CHECK_THROWS_MATCHES(parse_memory_path("tex"), UsageError,
                         Catch::Matchers::Message("unknown memory path 'tex' "
                                                  "(global, ldg, float4, "
                                                  "float4_ldg, texture or all)"));
    CHECK_THROWS_WITH(parse_memory_paths("tex"), contains("'tex'"));
    CHECK_THROWS_AS(parse_memory_paths("tex"), UsageError);
    CHECK_THROWS_AS(parse_memory_paths(""), UsageError);
    CHECK_THROWS_WITH(parse_memory_paths(""), contains("''"));
    CHECK_THROWS_AS(parse_memory_paths("global,,float4"), UsageError);
    CHECK_THROWS_WITH(parse_memory_paths("global,,float4"), contains("''"));
    CHECK_THROWS_AS(parse_memory_paths("global,"), UsageError);
    CHECK_THROWS_WITH(parse_memory_paths("global,Float4"), contains("'Float4'"));
    CHECK_THROWS_WITH(parse_memory_paths("global, float4"), contains("' float4'"));
    CHECK_THROWS_AS(parse_memory_path("all"), UsageError); // "all" is a list, not a path
  }
  SECTION("the CPU has global and float4; the GPU has every path") {
    for (const MemoryPath path : k_all_paths) {
      CAPTURE(to_string(path));
      const bool cpu = path == MemoryPath::global || path == MemoryPath::float4;
      CHECK(runs_on(path, Backend::cpu) == cpu);
      CHECK(runs_on(path, Backend::gpu));
      CHECK_NOTHROW(check_runs_on(path, Backend::gpu));
      if (cpu) {
        CHECK_NOTHROW(check_runs_on(path, Backend::cpu));
      } else {
        CHECK_THROWS_AS(check_runs_on(path, Backend::cpu), UsageError);
        CHECK_THROWS_WITH(check_runs_on(path, Backend::cpu),
                          contains(std::string("'") + to_string(path) + "'"));
        CHECK_THROWS_WITH(check_runs_on(path, Backend::cpu), contains("GPU"));
      }
    }
  }
  SECTION("the CPU trace refuses the GPU's paths, and a hit buffer of the wrong size") {
    const ch07::Bvh bvh = build_bvh(random_soup(50, 61), {});
    const PackedBvh packed = pack_bvh(bvh);
    const std::vector<RayF> rays(4, RayF{{0.0f, 0.0f, -9.0f}, {0.0f, 0.0f, 1.0f}});
    std::vector<MeshHit> hits(rays.size());
    for (const MemoryPath path : {MemoryPath::ldg, MemoryPath::float4_ldg, MemoryPath::texture})
      for (const Query query : {Query::closest, Query::any}) {
        CAPTURE(to_string(path));
        CHECK_THROWS_AS(trace_rays_path_cpu(path, query, bvh, packed, rays, hits), UsageError);
        CHECK_THROWS_WITH(trace_rays_path_cpu(path, query, bvh, packed, rays, hits),
                          contains(to_string(path)));
      }
    std::vector<MeshHit> short_hits(rays.size() - 1);
    CHECK_THROWS_AS(
        trace_rays_path_cpu(MemoryPath::float4, Query::closest, bvh, packed, rays, short_hits),
        Error);
  }
}

TEST_CASE("the texture limit: one line naming the texels and the limit", "[ch08]") {
  CHECK_NOTHROW(check_texel_count(0, 0, "the nodes"));
  CHECK_NOTHROW(check_texel_count(1000000, 1000000, "the nodes"));
  CHECK_NOTHROW(check_texel_count(999999, 1000000, "the nodes"));
  CHECK_THROWS_AS(check_texel_count(1000001, 1000000, "the nodes"), Error);
  CHECK_THROWS_WITH(check_texel_count(1000001, 1000000, "the nodes"),
                    contains("texture") && contains("the nodes") &&
                        contains("need 1 000 001 float4 texels") &&
                        contains("limit of 1 000 000") &&
                        contains("--memory global or float4"));
  // 2^27 texels, the usual limit, and one over it.
  CHECK_THROWS_WITH(check_texel_count(134217729, 134217728, "the triangles"),
                    contains("134 217 729") && contains("134 217 728") &&
                        contains("the triangles"));
  CHECK_THROWS_WITH(check_texel_count(1, 0, "x"),
                    contains("need 1 float4") && contains("limit of 0 "));
}

TEST_CASE("a texture object with no texels is refused before the GPU is asked", "[ch08]") {
  const long long live = TextureObject::live();
  CHECK_THROWS_AS(TextureObject(nullptr, 0), Error);
  CHECK_THROWS_WITH(TextureObject(nullptr, 0), contains("no texels"));
  CHECK_THROWS_AS(TextureObject(nullptr, 16), Error);
  {
    const TextureObject none;
    CHECK(none.handle() == 0);
  }
  CHECK(TextureObject::live() == live);
}

TEST_CASE("the shaded frame through the kept path is chapter 07's frame (CPU)", "[ch08]") {
  const auto [scene, bvh, extent, camera] = shaded_tree_case(2, {96, 64});
  const PackedBvh packed = pack_bvh(bvh);
  for (const bool smooth : {false, true}) {
    CAPTURE(smooth);
    const unsigned features = ch06::features_used(scene, smooth, true);
    const ch06::SceneView view = ch06::host_view(scene, features);
    std::vector<Rgba8> want(extent.pixel_count()), got(extent.pixel_count());
    std::vector<ch06::ShadedPixelRecord> want_records(want.size()), got_records(got.size());
    ch07::render_bvh_shaded(Backend::cpu, features, ch07::with_bvh(view, bvh.view()), camera,
                            extent, want.data(), want_records.data());
    render_kept_shaded(Backend::cpu, features, ch07::with_bvh(view, host_kept_view(packed)),
                       camera, extent, got.data(), got_records.data());
    CHECK(count_differing_pixels(want, got) == 0);
    CHECK(records_differing(want_records, got_records) == 0);
    int hits = 0;
    long long shadow_rays = 0, shadowed = 0;
    for (const ch06::ShadedPixelRecord& r : want_records) {
      hits += r.triangle >= 0 ? 1 : 0;
      shadow_rays += r.shadow_rays;
      shadowed += r.shadowed_facing;
    }
    CHECK(hits > 1000);
    CHECK(shadow_rays > 1000); // the any-hit query is exercised by the shadow rays
    CHECK(shadowed > 0);       // and some of them do find a blocker
  }
}
