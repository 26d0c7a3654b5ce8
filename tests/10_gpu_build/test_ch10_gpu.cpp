// Chapter 10 tests on the GPU: the same passes on CUDA threads give the CPU threads' tree bit
// for bit (nodes, their order, the triangle copies and ids), the LBVH of both code widths and
// PLOC, on random scenes, on equal codes and on the chain that makes 63-bit codes fall back,
// and PLOC's rounds on centroids that tie or chain (identical, collinear, ever wider spaced);
// the GPU refit gives the CPU refit's boxes, on a bent mesh and on the moving scene's frames;
// the GPU's collapse to the 4-wide tree is the CPU's, nodes and triangle records; frames made
// on the GPU move the vertices as the host reference does, and their trees pass the checkers.
#include <vector>

#include "rt_catch.h"

#include "07_bvh/bvh_cases.h"
#include "animation.h"
#include "build_cases.h"
#include "builders.h"
#include "check_bvh.h"
#include "collapse.h"
#include "gpu_build.h"
#include "gpu_guard.h"
#include "moving_frames.h"
#include "rt/device_buffer.h"
#include "wide_collapse.h"

using namespace rt;
using namespace rt::ch10;
using namespace rt::ch10::testing;

namespace {

void check_same_tree(const ch07::Bvh& gpu, const ch07::Bvh& cpu) {
  CHECK(rt::testing::same_bits(gpu.nodes, cpu.nodes));
  CHECK(rt::testing::same_bits(gpu.triangles, cpu.triangles));
  CHECK(gpu.triangle_ids == cpu.triangle_ids);
  CHECK(rt::testing::same_bits(gpu.bounds, cpu.bounds));
}

} // namespace

TEST_CASE("the GPU's LBVH and PLOC trees are the CPU's, bit for bit", "[ch10][gpu]") {
  RT_REQUIRE_GPU();
  const std::vector<Mesh> meshes = {
      rt::testing::mixed_scene(20000, 41),
      rt::testing::random_soup(100000, 43, Vec3f{1e5f, 0.0f, -3e4f}), identical_triangles(3000),
      power_of_two_chain(4096), rt::testing::single_triangle()};
  for (const Mesh& mesh : meshes) {
    for (const CodeWidth width : {CodeWidth::bits30, CodeWidth::bits63}) {
      CAPTURE(mesh.triangles.size(), to_string(width));
      const GpuBuild gpu = build_lbvh(Backend::gpu, mesh, width);
      const GpuBuild cpu = build_lbvh(Backend::cpu, mesh, width);
      CHECK(ch07::check_bvh(gpu.bvh, mesh).empty());
      check_same_tree(gpu.bvh, cpu.bvh);
      CHECK(gpu.codes == cpu.codes);
      CHECK(gpu.note == cpu.note);
    }
    const GpuBuild gpu = build_ploc(Backend::gpu, mesh);
    const GpuBuild cpu = build_ploc(Backend::cpu, mesh);
    CHECK(ch07::check_bvh(gpu.bvh, mesh).empty());
    check_same_tree(gpu.bvh, cpu.bvh);
  }
}

TEST_CASE("centroids that tie or chain: the GPU's PLOC takes the CPU's rounds to its tree",
          "[ch10][gpu]") {
  RT_REQUIRE_GPU();
  const std::vector<Mesh> meshes = {identical_triangles(200000), collinear_triangles(100000),
                                    exponentially_spaced_triangles(480)};
  for (const Mesh& mesh : meshes) {
    CAPTURE(mesh.triangles.size());
    const GpuBuild gpu = build_ploc(Backend::gpu, mesh);
    const GpuBuild cpu = build_ploc(Backend::cpu, mesh);
    CHECK(ch07::check_bvh(gpu.bvh, mesh).empty());
    check_same_tree(gpu.bvh, cpu.bvh);
    CHECK(gpu.rounds == cpu.rounds);
    CHECK(gpu.rounds_in_order == cpu.rounds_in_order);
    CHECK(gpu.rounds_in_order > 0);
    CHECK(gpu.rounds <= ploc_round_bound(static_cast<long long>(mesh.triangles.size())));
    CHECK(gpu.note.empty());
    for (const CodeWidth width : {CodeWidth::bits30, CodeWidth::bits63}) {
      CAPTURE(to_string(width));
      const GpuBuild lbvh = build_lbvh(Backend::gpu, mesh, width);
      CHECK(ch07::check_bvh(lbvh.bvh, mesh).empty());
      check_same_tree(lbvh.bvh, build_lbvh(Backend::cpu, mesh, width).bvh);
    }
  }
}

TEST_CASE("the GPU's refit is the CPU's, bit for bit", "[ch10][gpu]") {
  RT_REQUIRE_GPU();
  const Mesh scene = rt::testing::mixed_scene(20000, 47);
  const Mesh moved = bent(scene, 0.6f);
  ch07::Bvh lbvh = build_lbvh(Backend::cpu, scene, CodeWidth::bits30).bvh;
  ch07::Bvh sah = ch07::build_bvh(scene, {});
  for (const ch07::Bvh* tree : {&lbvh, &sah}) {
    ch07::Bvh on_gpu = *tree, on_cpu = *tree;
    refit_bvh(Backend::gpu, on_gpu, moved);
    refit_bvh(Backend::cpu, on_cpu, moved);
    CHECK(ch07::check_bvh(on_gpu, moved).empty());
    check_same_tree(on_gpu, on_cpu);
  }
}

TEST_CASE("the moving scene's frames: GPU builds and refits are the CPU's", "[ch10][gpu]") {
  RT_REQUIRE_GPU();
  const ch04::Mesh start = moving_scene_at(0.0, 128).geometry;
  const ch04::Mesh later = moving_scene_at(2.0, 128).geometry;
  for (const Builder builder : {Builder::lbvh, Builder::lbvh63, Builder::ploc}) {
    CAPTURE(to_string(builder));
    ch07::Bvh on_gpu = build_tree(builder, Backend::gpu, start).bvh;
    ch07::Bvh on_cpu = build_tree(builder, Backend::cpu, start).bvh;
    check_same_tree(on_gpu, on_cpu);
    refit_bvh(Backend::gpu, on_gpu, later);
    refit_bvh(Backend::cpu, on_cpu, later);
    CHECK(ch07::check_bvh(on_gpu, later).empty());
    check_same_tree(on_gpu, on_cpu);
  }
}

TEST_CASE("the GPU's collapse to the 4-wide tree is the CPU's, bit for bit", "[ch10][gpu]") {
  RT_REQUIRE_GPU();
  const std::vector<Mesh> meshes = {rt::testing::mixed_scene(20000, 73),
                                    identical_triangles(3000), power_of_two_chain(4096),
                                    rt::testing::single_triangle(), huge_soup()};
  for (const Mesh& mesh : meshes) {
    for (const Builder builder : {Builder::lbvh, Builder::ploc, Builder::hploc}) {
      const ch07::Bvh binary = build_tree(builder, Backend::cpu, mesh).bvh;
      for (const CollapseRule rule : {CollapseRule::sah, CollapseRule::depth}) {
        CAPTURE(mesh.triangles.size(), to_string(builder), to_string(rule));
        const ch09::Wide4PackedBvh gpu = collapse_to_wide4(Backend::gpu, binary, rule);
        const ch09::Wide4PackedBvh cpu = collapse_to_wide4(Backend::cpu, binary, rule);
        CHECK(ch09::check_wide_tree(gpu, mesh).empty());
        CHECK(rt::testing::same_bits(gpu.nodes, cpu.nodes));
        CHECK(rt::testing::same_bits(gpu.triangles, cpu.triangles));
      }
    }
  }
}

TEST_CASE("frames made on the GPU: the reference's vertices, trees that pass the checkers",
          "[ch10][gpu]") {
  RT_REQUIRE_GPU();
  const int detail = 128;
  const Extent extent{64, 36};
  const ch03::Camera<float> camera = ch03::make_camera<float>(moving_scene_camera(), extent);
  DeviceBuffer<Rgba8> pixels(extent.pixel_count());
  for (const Update update : {Update::rebuild, Update::refit}) {
    MovingFrames frames(Backend::gpu, Builder::lbvh, detail);
    for (const double time : {0.0, 1.3}) {
      CAPTURE(to_string(update), time);
      frames.frame(time, update, camera, extent, pixels.data());
      ch04::Mesh reference = moving_scene_at(time, detail).geometry;
      const std::vector<Vec3f> moved = frames.vertices();
      REQUIRE(moved.size() == reference.vertices.size());
      float worst = 0.0f;
      for (std::size_t v = 0; v < moved.size(); ++v)
        worst = std::max(worst, length(moved[v] - reference.vertices[v]));
      CHECK(worst < 2e-5f);
      reference.vertices = moved;
      CHECK(ch07::check_bvh(frames.binary_tree(), reference).empty());
      CHECK(ch09::check_wide_tree(frames.wide_tree(), reference).empty());
    }
  }
}
