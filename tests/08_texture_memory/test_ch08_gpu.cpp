// Chapter 08 tests on the GPU: every memory path gives chapter 07's CPU hits bit for bit (both
// queries, several tree shapes, hostile rays, the empty tree and a single triangle); the camera
// rays made in the kernel, with the camera and tree as kernel parameters or in __constant__
// memory, give the CPU's hits of the protocol's camera rays; texture objects are never leaked
// (moves, exceptions, thousands made and destroyed); and the shaded frame through the kept
// path is chapter 07's frame.
#include <limits>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include "rt_catch.h"

#include "06_lambertian_shading/shading_cases.h"
#include "07_bvh/bvh_cases.h"
#include "memory_cases.h"

#include "bvh_build.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "gpu_guard.h"
#include "kept_render.h"
#include "memory_paths.h"
#include "memory_trace.h"
#include "obj_loader.h"
#include "packed_bvh.h"
#include "protocol.h"
#include "rt/device_buffer.h"
#include "rt/error.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "texture_object.h"

using namespace rt;
using namespace rt::ch08;
using namespace rt::testing;
using ch04::Mesh;
using ch04::MeshHit;
using ch07::build_bvh;
using ch07::Query;
using ch07::SplitMethod;

namespace {

// A closed sphere over a flat grid box (faces on slab planes), and a soup of small triangles.
Mesh scene_for_tests(unsigned seed) {
  Mesh mesh = sphere_over_box();
  ch04::append_mesh(mesh, random_soup(2000, seed, SoupLayout{{}, 3.5f, 0.01f, 0.4f}));
  return mesh;
}

// Random rays (some with a finite tmax or a tmin), rays at vertices and edge midpoints of the
// mesh, rays along the box's top face, and the hostile rays that must miss at once.
std::vector<RayF> rays_for_tests(const Mesh& mesh, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<RayF> rays = rays_towards_origin(rng, count, Intervals::some_finite);
  for (std::size_t k = 0; k < mesh.triangles.size(); k += 3) {
    const auto& t = mesh.triangles[k];
    const Vec3f o{6.0f * unit(rng), 6.0f * unit(rng), 6.0f * unit(rng)};
    rays.push_back({o, mesh.vertices[t.v0] - o});
    rays.push_back({o, (mesh.vertices[t.v1] + mesh.vertices[t.v2]) * 0.5f - o});
  }
  for (int a = 0; a <= 16; ++a) {
    const float u = -3.0f + 0.375f * a;
    rays.push_back({{u, -1.5f, 5.0f}, {0.0f, -0.0f, -1.0f}}); // along the box's top face
    rays.push_back({{u, 5.0f, u}, {-0.0f, -1.0f, 0.0f}});     // straight down onto it
    rays.push_back({{-3.0f, -1.5f, u}, {1.0f, 0.0f, 0.0f}});  // along an edge's planes
  }
  const std::vector<RayF> hostile = hostile_rays({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f});
  rays.insert(rays.end(), hostile.begin(), hostile.end());
  rays.push_back({{1e6f, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f}}); // from far away
  return rays;
}

// The hit buffer is poisoned first: a hit the kernel does not write shows up as a difference.
std::vector<MeshHit> trace_gpu(MemoryPath path, Query query, const DeviceTrees& trees,
                               const std::vector<RayF>& rays) {
  const DeviceBuffer<RayF> d_rays{std::span<const RayF>(rays)};
  DeviceBuffer<MeshHit> d_hits(rays.size());
  d_hits.fill_bytes(0x5a);
  trace_rays_path_gpu(path, query, trees, d_rays.data(), static_cast<int>(rays.size()),
                      d_hits.data());
  return d_hits.to_host();
}

// Every path and query of `bvh` on the GPU against chapter 07's CPU hits.
void check_every_path(const ch07::Bvh& bvh, const std::vector<RayF>& rays, int min_hits) {
  const PackedBvh packed = pack_bvh(bvh);
  const DeviceTrees trees(bvh, packed, /*with_textures=*/true);
  REQUIRE(trees.has_textures());
  for (const Query query : {Query::closest, Query::any}) {
    const std::vector<MeshHit> reference = reference_hits(query, bvh, rays);
    CHECK(count_hits(reference) >= min_hits);
    for (const MemoryPath path : k_all_paths) {
      CAPTURE(to_string(path), ch07::to_string(query));
      CHECK(first_difference(trace_gpu(path, query, trees, rays), reference) == -1);
    }
  }
}

} // namespace

TEST_CASE("every memory path on the GPU gives chapter 07's CPU hits bit for bit",
          "[ch08][gpu]") {
  RT_REQUIRE_GPU();
  const Mesh mesh = scene_for_tests(5);
  const std::vector<RayF> rays = rays_for_tests(mesh, 20000, 7);
  struct Shape {
    SplitMethod method;
    int leaf;
  };
  for (const Shape shape : {Shape{SplitMethod::sah, 1}, Shape{SplitMethod::sah, 4},
                            Shape{SplitMethod::sah, 8}, Shape{SplitMethod::median, 4}}) {
    CAPTURE(ch07::to_string(shape.method), shape.leaf);
    check_every_path(build_bvh(mesh, options_of(shape.method, shape.leaf)), rays, 8000);
  }
}

TEST_CASE("ids whose bits are NaN floats survive every GPU path", "[ch08][gpu]") {
  RT_REQUIRE_GPU();
  // The ids ride in float lanes (the records' w): a load that treated them as floats and
  // quietened or canonicalised a NaN would change them. Real meshes never have such ids; the
  // loads must still be bit copies.
  const Mesh mesh = scene_for_tests(11);
  ch07::Bvh bvh = build_bvh(mesh, {});
  const std::uint32_t patterns[] = {0x7fc00001u, 0x7f800001u, 0xff800001u, 0xffc00000u,
                                    0xffffffffu, 0x7fffffffu, 0x80000000u, 0x00000001u};
  for (std::size_t k = 0; k < bvh.triangle_ids.size(); ++k)
    bvh.triangle_ids[k] =
        static_cast<int>(patterns[k % std::size(patterns)]) ^ static_cast<int>((k & 0xff) << 8);
  const std::vector<RayF> rays = rays_for_tests(mesh, 5000, 13);
  std::vector<MeshHit> reference = reference_hits(Query::closest, bvh, rays);
  int hits = 0;
  for (const MeshHit& h : reference) hits += h.t < std::numeric_limits<float>::infinity();
  CHECK(hits > 2000);
  const PackedBvh packed = pack_bvh(bvh);
  const DeviceTrees trees(bvh, packed, true);
  for (const MemoryPath path : k_all_paths) {
    CAPTURE(to_string(path));
    CHECK(first_difference(trace_gpu(path, Query::closest, trees, rays), reference) == -1);
  }
}

TEST_CASE("the empty tree and a single triangle on every GPU path", "[ch08][gpu]") {
  RT_REQUIRE_GPU();
  const long long live = TextureObject::live();
  std::vector<RayF> rays;
  for (int i = -8; i <= 8; ++i)
    for (int j = -8; j <= 8; ++j)
      rays.push_back({{0.125f * i, 0.125f * j, 0.0f}, {0.0f, 0.0f, 1.0f}});
  rays.push_back({{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}});            // away from it
  rays.push_back({{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, 2.0f}); // stops short
  rays.push_back({{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}});             // no direction

  SECTION("empty: textures are skipped, every path misses everything") {
    const ch07::Bvh empty = build_bvh(Mesh{}, {});
    const PackedBvh packed = pack_bvh(empty);
    const DeviceTrees trees(empty, packed, /*with_textures=*/true);
    CHECK(trees.has_textures());
    CHECK(trees.node_texture() == 0);
    CHECK(trees.triangle_texture() == 0);
    CHECK(TextureObject::live() == live);
    for (const MemoryPath path : k_all_paths)
      for (const Query query : {Query::closest, Query::any}) {
        CAPTURE(to_string(path), ch07::to_string(query));
        const std::vector<MeshHit> hits = trace_gpu(path, query, trees, rays);
        CHECK(first_difference(hits, std::vector<MeshHit>(rays.size())) == -1);
      }
  }
  SECTION("a single triangle: one node, an empty child, the same hits as the CPU") {
    const ch07::Bvh bvh = build_bvh(single_triangle(), {});
    REQUIRE(bvh.nodes.size() == 1);
    const PackedBvh packed = pack_bvh(bvh);
    const DeviceTrees trees(bvh, packed, true);
    CHECK(trees.node_texture() != 0);
    CHECK(trees.triangle_texture() != 0);
    CHECK(TextureObject::live() == live + 2);
    for (const Query query : {Query::closest, Query::any}) {
      const std::vector<MeshHit> reference = reference_hits(query, bvh, rays);
      CHECK(reference[8 * 17 + 8].triangle == 0); // the ray through (0, 0)
      CHECK(reference[8 * 17 + 8].t == 3.0f);
      CHECK(count_hits(reference) > 50);
      CHECK(reference[rays.size() - 2].triangle == -1);
      for (const MemoryPath path : k_all_paths) {
        CAPTURE(to_string(path), ch07::to_string(query));
        CHECK(first_difference(trace_gpu(path, query, trees, rays), reference) == -1);
      }
    }
  }
  CHECK(TextureObject::live() == live);
}

TEST_CASE("DeviceTrees: sizes, the texture path's precondition, a foreign packed tree",
          "[ch08][gpu]") {
  RT_REQUIRE_GPU();
  const Mesh mesh = scene_for_tests(17);
  const ch07::Bvh bvh = build_bvh(mesh, {});
  const PackedBvh packed = pack_bvh(bvh);
  const long long live = TextureObject::live();
  {
    const DeviceTrees plain(bvh, packed, /*with_textures=*/false);
    CHECK_FALSE(plain.has_textures());
    CHECK(plain.node_texture() == 0);
    CHECK(TextureObject::live() == live);
    const std::size_t structs =
        bvh.nodes.size() * 64 + bvh.triangles.size() * (sizeof(ch04::TriangleF) + 4);
    const std::size_t records = bvh.nodes.size() * 64 + bvh.triangles.size() * 48;
    CHECK(plain.bytes(MemoryPath::global) == structs);
    CHECK(plain.bytes(MemoryPath::ldg) == structs);
    for (const MemoryPath path :
         {MemoryPath::float4, MemoryPath::float4_ldg, MemoryPath::texture})
      CHECK(plain.bytes(path) == records);
    CHECK(device_tree_bytes(bvh) == structs + records);
    // The texture path needs the textures; the other paths do not.
    const std::vector<RayF> rays = rays_for_tests(mesh, 100, 19);
    CHECK_THROWS_AS(trace_gpu(MemoryPath::texture, Query::closest, plain, rays), Error);
    CHECK_THROWS_WITH(trace_gpu(MemoryPath::texture, Query::any, plain, rays),
                      contains("texture"));
    CHECK(first_difference(trace_gpu(MemoryPath::float4_ldg, Query::closest, plain, rays),
                           reference_hits(Query::closest, bvh, rays)) == -1);
    // Views of the same device arrays.
    CHECK(plain.ldg_tree().nodes == plain.global_tree().nodes);
    CHECK(plain.kept().records.nodes == plain.float4_tree().records.nodes);
    CHECK(plain.kept().node_count == static_cast<int>(bvh.nodes.size()));
  }
  // Another tree's records: refused.
  const ch07::Bvh other = build_bvh(mesh, options_of(SplitMethod::sah, 1));
  REQUIRE(other.nodes.size() != bvh.nodes.size());
  CHECK_THROWS_AS(DeviceTrees(bvh, pack_bvh(other), true), Error);
  CHECK(TextureObject::live() == live);
}

TEST_CASE("camera rays made in the kernel give the protocol's camera hits", "[ch08][gpu]") {
  RT_REQUIRE_GPU();
  const Mesh mesh = ch05::load_obj(RT_ASSETS_DIR "/torus_knot_100k.obj.gz").geometry;
  const ch07::Bvh bvh = build_bvh(mesh, {});
  const PackedBvh packed = pack_bvh(bvh);
  const DeviceTrees trees(bvh, packed, false);
  const ch07::PinholeCamera camera =
      ch07::make_protocol_camera(ch07::auto_frame_view(bvh.bounds), 160, 90);
  const std::vector<RayF> rays = ch07::camera_rays_cpu(camera);
  REQUIRE(rays.size() == 160u * 90u);
  std::vector<MeshHit> reference(rays.size());
  trace_rays_path_cpu(MemoryPath::global, Query::closest, bvh, packed, rays, reference);
  CHECK(count_hits(reference) > 1000); // the knot covers about a tenth of the frame

  const auto launched = [&](const CameraTrace& trace, const ch07::PinholeCamera& c) {
    DeviceBuffer<MeshHit> d_hits(static_cast<std::size_t>(c.width) * c.height);
    d_hits.fill_bytes(0x5a);
    trace.launch(d_hits.data());
    return d_hits.to_host();
  };
  const CameraTrace parameters(trees, camera, ConstantsIn::parameters);
  const CameraTrace constant(trees, camera, ConstantsIn::constant_memory);
  CHECK(parameters.registers() > 0);
  CHECK(constant.registers() > 0);
  CHECK(first_difference(launched(parameters, camera), reference) == -1);
  CHECK(first_difference(launched(constant, camera), reference) == -1);

  // A second CameraTrace in __constant__ memory refills the one symbol: the first may no
  // longer launch; the second traces its own camera, and the kernel-parameter one still
  // gives the first camera's hits.
  const ch07::PinholeCamera other_camera =
      ch07::make_protocol_camera(ch07::auto_frame_view(bvh.bounds), 120, 68);
  const std::vector<RayF> other_rays = ch07::camera_rays_cpu(other_camera);
  std::vector<MeshHit> other_reference(other_rays.size());
  trace_rays_path_cpu(MemoryPath::global, Query::closest, bvh, packed, other_rays,
                      other_reference);
  const CameraTrace second(trees, other_camera, ConstantsIn::constant_memory);
  CHECK_THROWS_AS(launched(constant, camera), Error);
  CHECK_THROWS_WITH(launched(constant, camera), contains("__constant__"));
  CHECK(first_difference(launched(second, other_camera), other_reference) == -1);
  CHECK(first_difference(launched(parameters, camera), reference) == -1);
}

TEST_CASE("texture objects are never leaked", "[ch08][gpu]") {
  RT_REQUIRE_GPU();
  const long long start = TextureObject::live();
  const Mesh mesh = ch04::make_icosphere(2, {0.0, 0.0, 0.0}, 1.0);
  const ch07::Bvh bvh = build_bvh(mesh, {});
  const PackedBvh packed = pack_bvh(bvh);

  SECTION("DeviceTrees owns two, and frees them at the end of its scope") {
    {
      const DeviceTrees trees(bvh, packed, true);
      CHECK(TextureObject::live() == start + 2);
      CHECK(trees.node_texture() != 0);
      CHECK(trees.triangle_texture() != 0);
      CHECK(trees.node_texture() != trees.triangle_texture());
    }
    CHECK(TextureObject::live() == start);
  }
  SECTION("an exception thrown mid-scope frees them") {
    try {
      const DeviceTrees trees(bvh, packed, true);
      CHECK(TextureObject::live() == start + 2);
      throw std::runtime_error("mid-scope");
    } catch (const std::runtime_error&) {
    }
    CHECK(TextureObject::live() == start);
  }
  SECTION("moves hand the handle over; self-move keeps it") {
    const DeviceBuffer<float4> records{std::span<const float4>(packed.nodes)};
    {
      TextureObject a(records.data(), records.size());
      const cudaTextureObject_t handle = a.handle();
      CHECK(handle != 0);
      CHECK(TextureObject::live() == start + 1);
      TextureObject b(std::move(a));
      CHECK(a.handle() == 0); // NOLINT(bugprone-use-after-move): moved-from is empty
      CHECK(b.handle() == handle);
      CHECK(TextureObject::live() == start + 1);

      TextureObject c(records.data(), records.size());
      CHECK(TextureObject::live() == start + 2);
      c = std::move(b); // c's own texture is destroyed, b's taken over
      CHECK(c.handle() == handle);
      CHECK(b.handle() == 0); // NOLINT(bugprone-use-after-move)
      CHECK(TextureObject::live() == start + 1);

      TextureObject& alias = c;
      c = std::move(alias); // self-move: neither destroyed nor emptied
      CHECK(c.handle() == handle);
      CHECK(TextureObject::live() == start + 1);

      TextureObject empty;
      c = std::move(empty); // an empty one moved in frees c's
      CHECK(c.handle() == 0);
      CHECK(TextureObject::live() == start);
      c = TextureObject(records.data(), records.size());
      CHECK(c.handle() != 0);
      CHECK(TextureObject::live() == start + 1);
    }
    CHECK(TextureObject::live() == start);
  }
  SECTION("thousands made and destroyed: none left, none refused") {
    const DeviceBuffer<float4> records{std::span<const float4>(packed.triangles)};
    for (int i = 0; i < 3000; ++i) {
      TextureObject t(records.data(), records.size());
      if (t.handle() == 0 || TextureObject::live() != start + 1) {
        CAPTURE(i);
        FAIL("texture object " << i << " not made, or one left over");
      }
    }
    CHECK(TextureObject::live() == start);
    // And the trees still work after all that.
    const DeviceTrees trees(bvh, packed, true);
    const std::vector<RayF> rays = rays_for_tests(mesh, 500, 23);
    CHECK(first_difference(trace_gpu(MemoryPath::texture, Query::closest, trees, rays),
                           reference_hits(Query::closest, bvh, rays)) == -1);
  }
  SECTION("no texels, or more than the GPU allows, is an error") {
    CHECK_THROWS_AS(TextureObject(nullptr, 0), Error);
    const DeviceBuffer<float4> records{std::span<const float4>(packed.nodes)};
    CHECK_THROWS_AS(TextureObject(records.data(), 0), Error);
    const std::size_t limit = texture_texel_limit();
    CHECK(limit >= 65536);
    CHECK_NOTHROW(check_texel_count(limit, limit, "the nodes"));
    CHECK_THROWS_AS(check_texel_count(limit + 1, limit, "the nodes"), Error);
    // A texture wider than the limit is refused before CUDA is asked (the pointer is never
    // read: the count is checked first).
    CHECK_THROWS_WITH(TextureObject(records.data(), limit + 1), contains("texture path"));
  }
  CHECK(TextureObject::live() == start);
}

TEST_CASE("every path's traversal kernel has a register count", "[ch08][gpu]") {
  RT_REQUIRE_GPU();
  for (const MemoryPath path : k_all_paths)
    for (const Query query : {Query::closest, Query::any}) {
      CAPTURE(to_string(path), ch07::to_string(query));
      const int registers = path_kernel_registers(path, query);
      CHECK(registers > 0);
      CHECK(registers <= 255);
    }
}

TEST_CASE("GPU shaded frame through the kept path is chapter 07's frame", "[ch08][gpu]") {
  RT_REQUIRE_GPU();
  const auto [scene, bvh, extent, camera] = shaded_tree_case(3, {160, 90});
  const PackedBvh packed = pack_bvh(bvh);
  const DeviceTrees trees(bvh, packed, false);
  const std::size_t pixels = static_cast<std::size_t>(extent.pixel_count());
  for (const bool smooth : {false, true}) {
    CAPTURE(smooth);
    const unsigned features = ch06::features_used(scene, smooth, true);
    const ch06::DeviceShadedScene d_scene(scene, features);
    DeviceBuffer<Rgba8> d_kept(pixels), d_bvh(pixels);
    DeviceBuffer<ch06::ShadedPixelRecord> d_kept_records(pixels), d_bvh_records(pixels);
    d_kept.fill_bytes(0x5a);
    d_kept_records.fill_bytes(0x5a);
    render_kept_shaded(Backend::gpu, features, ch07::with_bvh(d_scene.view(), trees.kept()),
                       camera, extent, d_kept.data(), d_kept_records.data());
    ch07::render_bvh_shaded(Backend::gpu, features,
                            ch07::with_bvh(d_scene.view(), trees.global_tree()), camera, extent,
                            d_bvh.data(), d_bvh_records.data());
    const std::vector<Rgba8> kept = d_kept.to_host();
    CHECK(count_differing_pixels(kept, d_bvh.to_host()) == 0);
    const std::vector<ch06::ShadedPixelRecord> a = d_kept_records.to_host();
    const std::vector<ch06::ShadedPixelRecord> b = d_bvh_records.to_host();
    CHECK(records_differing(a, b) == 0);
    int hits = 0;
    long long shadow_rays = 0;
    for (const ch06::ShadedPixelRecord& r : a) {
      hits += r.triangle >= 0 ? 1 : 0;
      shadow_rays += r.shadow_rays;
    }
    CHECK(hits > 3000);
    CHECK(shadow_rays > 3000);
    // And the kept path on the CPU draws the same frame.
    std::vector<Rgba8> cpu(pixels);
    render_kept_shaded(Backend::cpu, features,
                       ch07::with_bvh(ch06::host_view(scene, features), host_kept_view(packed)),
                       camera, extent, cpu.data());
    CHECK(count_differing_pixels(kept, cpu) == 0);
  }
}
