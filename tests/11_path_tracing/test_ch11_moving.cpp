// Chapter 11 tests of the moving scene kept on the backend (moving_path.h): after any number of
// frames, the renderer traces the image a renderer made afresh for the same vertices traces,
// bit for bit; its vertices are chapter 10's moving scene at that time, to float's rounding;
// the sums start again at every move; the waving model moves as chapter 10's does; and on the
// GPU, the frames give the CPU's sums bit for bit.
//
// Why "the same vertices" and not moving_path_scene's own: the frames move the vertices in
// float (motion.h's templates on the backend), the host's reference scene in double, rounded
// once at the end. The two differ in the last bits of some vertices, so their LBVHs may differ,
// and a path that grazes an edge may part ways. The bit-for-bit oracle is a renderer made from
// the moved vertices themselves; against moving_path_scene's, the tests state a tolerance.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rt_catch.h"

#include "animation.h"
#include "collapse.h"
#include "gpu_guard.h"
#include "moving_path.h"
#include "path_cases.h"
#include "path_report.h"
#include "run_program.h"

using namespace rt;
using namespace rt::ch11;
using namespace rt::ch11::testing;

namespace {

const Extent k_small{40, 30};
constexpr int k_detail = 24; // 576 torus triangles, beside the spheres' 5 120 and the floor's
const RenderSettings k_megakernel{PathVariant::megakernel, KernelKind::specialised,
                                  Strategy::mis};

// The moving scene (or the waving `model`) at `time`, lit as the program lights it.
PathScene lit_scene(double time, const ch04::Mesh* model) {
  PathScene scene = lit_moving_scene(time, k_detail);
  if (model) {
    const Environment environment = scene.environment;
    scene = moving_path_scene(time, k_detail, model);
    scene.environment = environment;
  }
  return scene;
}

double time_of(int frame) { return frame * ch10::k_seconds_per_frame; }

// The largest distance between a moved vertex and the reference's.
float worst_distance(const std::vector<Vec3f>& moved, const std::vector<Vec3f>& reference) {
  REQUIRE(moved.size() == reference.size());
  float worst = 0.0f;
  for (std::size_t v = 0; v < moved.size(); ++v)
    worst = std::max(worst, length(moved[v] - reference[v]));
  return worst;
}

// `samples` samples by a renderer made afresh for `scene`, its tree chapter 10's LBVH.
std::vector<float4> fresh_sums(const PathScene& scene, Backend backend, int samples,
                               const RenderSettings& settings = k_megakernel) {
  PathRenderer fresh(scene, backend, TreeBuild::lbvh);
  fresh.restart(ch10::moving_scene_camera(), k_small);
  fresh.add_samples(settings, samples);
  return fresh.sums();
}

// A small closed model for the waving path: a box of 6 x 4 x 4 x 2 triangles, fitted.
ch04::Mesh small_model() {
  return ch10::fit_moving_model(ch04::make_box({-1.0, 0.0, -0.5}, {1.0, 1.5, 0.5}, 4));
}

// Moves `renderer` frame by frame to `last`, a sample at each, as the window does; then
// `samples` samples of the last frame.
void run_frames(MovingPathRenderer& renderer, int last, int samples,
                const RenderSettings& settings = k_megakernel) {
  renderer.restart(ch10::moving_scene_camera(), k_small);
  for (int frame = 1; frame <= last; ++frame) {
    renderer.add_samples(settings, 1);
    renderer.move_to(time_of(frame));
  }
  renderer.add_samples(settings, samples);
}

} // namespace

TEST_CASE("moving on the backend: after k frames, the image of a renderer made for the moved "
          "vertices, bit for bit, and the sums started again at each move",
          "[ch11][moving]") {
  const PathScene start = lit_scene(0.0, nullptr);
  for (const int frames : {1, 7}) {
    CAPTURE(frames);
    MovingPathRenderer moving(start, Backend::cpu, k_detail);
    run_frames(moving, frames, 3);
    CHECK(moving.samples() == 3); // the samples of earlier frames are gone
    for (const float4& s : moving.sums()) REQUIRE(s.w == 3.0f); // from every pixel's sum

    // The vertices are the scene's at that time, to float's rounding.
    PathScene later = lit_scene(time_of(frames), nullptr);
    const std::vector<Vec3f> moved = moving.vertices();
    CHECK(worst_distance(moved, later.mesh.vertices) < 2e-5f);
    CHECK(worst_distance(moved, start.mesh.vertices) > 1e-2f); // and they did move

    // The tree the kernels read is a valid tree of the moved vertices.
    ch04::Mesh traced = later.mesh;
    traced.vertices = moved;
    CHECK(ch09::check_wide_tree(moving.wide_tree(), traced).empty());

    // The same vertices: the same LBVH, the same paths, the same sums.
    later.mesh.vertices = moved;
    const std::vector<float4> sums = moving.sums();
    CHECK(same_sums(sums, fresh_sums(later, Backend::cpu, 3)));
    CHECK(pixel_statistics(moving.mean_radiance()).mean > 0.1); // lit: the sums can differ
  }
}

TEST_CASE("moving on the backend: against a renderer of moving_path_scene's own vertices, "
          "the image agrees to within float's rounding of the motion",
          "[ch11][moving]") {
  const int frames = 5;
  MovingPathRenderer moving(lit_scene(0.0, nullptr), Backend::cpu, k_detail);
  run_frames(moving, frames, 4);
  const std::vector<float4> a = moving.sums();
  const std::vector<float4> b =
      fresh_sums(lit_scene(time_of(frames), nullptr), Backend::cpu, 4);
  // Vertices 2e-5 apart move a camera ray's hit point by as little; a path's later
  // directions come from the same numbers, so a pixel changes in its last bits only (here
  // 178 of 1 200 pixels differ, by at most 1e-6 of their sums), unless a ray passes within
  // that distance of an edge and finds another triangle: at most 1% of the pixels may.
  int far_apart = 0;
  double sum_a = 0.0, sum_b = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double pa = a[i].x + a[i].y + a[i].z, pb = b[i].x + b[i].y + b[i].z;
    sum_a += pa, sum_b += pb;
    far_apart += std::abs(pa - pb) > 1e-4 * std::max(1.0, std::abs(pb));
  }
  CAPTURE(far_apart, sum_a, sum_b);
  CHECK(far_apart <= int(a.size()) / 100);
  CHECK(std::abs(sum_a - sum_b) <= 1e-4 * sum_b);
}

TEST_CASE("moving on the backend: the waving model moves as chapter 10's, and renders as a "
          "renderer made for its moved vertices",
          "[ch11][moving]") {
  const ch04::Mesh model = small_model();
  const PathScene start = lit_scene(0.0, &model);
  REQUIRE(start.mesh.triangles.size() == model.triangles.size() + 4 * 1280 + 6 * 4 * 4 * 2);
  const int frames = 6;
  MovingPathRenderer moving(start, Backend::cpu, k_detail, &model);
  run_frames(moving, frames, 3);
  PathScene later = lit_scene(time_of(frames), &model);
  const std::vector<Vec3f> moved = moving.vertices();
  CHECK(worst_distance(moved, later.mesh.vertices) < 2e-5f);
  const std::vector<Vec3f> waved = ch10::waving_model(model, time_of(frames)).vertices;
  CHECK(worst_distance({moved.begin(), moved.begin() + std::ssize(waved)}, waved) < 2e-5f);
  later.mesh.vertices = moved;
  CHECK(same_sums(moving.sums(), fresh_sums(later, Backend::cpu, 3)));
  // The model is in the picture: without it (the torus in its place), another image.
  CHECK_FALSE(same_sums(moving.sums(),
                        fresh_sums(lit_scene(time_of(frames), nullptr), Backend::cpu, 3)));
}

TEST_CASE("moving on the backend: a scene that emits, or another scene's triangles, is "
          "refused",
          "[ch11][moving]") {
  PathScene lamp = lit_scene(0.0, nullptr);
  lamp.materials[5].emission = {1.0f, 1.0f, 1.0f}; // the floor glows: its table would move
  lamp.lights = build_light_table(lamp);
  REQUIRE_FALSE(lamp.lights.triangles.empty());
  CHECK_THROWS_AS(MovingPathRenderer(lamp, Backend::cpu, k_detail), InputError);
  CHECK_THROWS_AS(MovingPathRenderer(lit_scene(0.0, nullptr), Backend::cpu, k_detail + 2),
                  InputError);
}

TEST_CASE("moving on the backend: the report's row gives the frame's four parts",
          "[ch11][moving]") {
  MovingPathRenderer moving(lit_moving_scene(0.0, 8), Backend::cpu, 8);
  Report report("moving", "Mpaths/s", "none");
  std::ostringstream lines;
  add_moving_rows(moving, {}, ch10::moving_scene_camera(), {8, 6}, 3, report, lines,
                  std::chrono::milliseconds(0));
  const std::string text = lines.str();
  CAPTURE(text);
  CHECK_THAT(text, rt::testing::contains("moving scene: 33% (1 of 3 frames)"));
  REQUIRE(report.rows().size() == 1);
  const ReportRow& row = report.rows()[0];
  CAPTURE(row.error);
  CHECK_THAT(row.error, rt::testing::contains("ms animate + "));
  CHECK_THAT(row.error, rt::testing::contains("ms collapse + "));
  CHECK_THAT(row.error, rt::testing::contains("over 3 frames; 0 NaN/Inf samples"));
  double parts = 0.0;
  for (const auto& [name, value] : row.metrics)
    if (name == "animate_ms" || name == "tree_ms" || name == "collapse_ms" ||
        name == "render_ms") {
      CHECK(value >= 0.0);
      parts += value;
    }
  CHECK(std::abs(parts - row.ms_per_frame) <=
        1e-9 * std::max(1.0, row.ms_per_frame)); // the row is their sum
  CHECK(moving.samples() == 1);                  // the last frame's one sample
}

TEST_CASE("program: --moving --scene path-traces the model waving in the torus's place",
          "[ch11][moving]") {
  namespace fs = std::filesystem;
  const rt::testing::HeadlessCpuProgram run_program(RT_CH11_PROGRAM);
  const fs::path folder = rt::testing::temp_folder("rt_ch11_moving");
  const fs::path model = folder / "tetrahedron.obj";
  std::ofstream(model) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n"
                          "f 2 3 4\n";
  const std::string image = (folder / "waving.png").string();
  const rt::testing::ProgramRun run =
      run_program("--moving --scene " + model.string() +
                  " --frames 2 --width 24 --height 16 --spp 2 --output " + image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, rt::testing::contains("waving model (4 triangles)"));
  CHECK_THAT(run.output, rt::testing::contains("ms animate + "));
  CHECK(fs::file_size(image) > 100);
  const rt::testing::RefusedInput refused[] = {
      {"--moving --scene " + model.string() + " --detail 16", 2, "--detail sizes the torus"},
      {"--moving --convergence", 2, "--moving renders frames of a moving scene"},
  };
  rt::testing::check_refused(run_program, refused);
}

TEST_CASE("GPU: the moving scene kept on the GPU gives the CPU's sums bit for bit, frame by "
          "frame, for the torus and the waving model",
          "[ch11][moving][gpu]") {
  RT_REQUIRE_GPU();
  // The GPU moves the vertices with its own sinf and cosf, and nvcc fuses the motion's
  // a * b + c (moving_frames.cu is chapter 10's, compiled with FMAs): its vertices may differ
  // from the CPU's in the last bits. The oracle is the CPU's renderer made for the GPU's own
  // vertices: from them chapter 10's LBVH makes the same tree on both backends, and the paths
  // are the same bit for bit (test_ch11_gpu.cpp says why).
  const ch04::Mesh model = small_model();
  for (const ch04::Mesh* shape : {static_cast<const ch04::Mesh*>(nullptr), &model}) {
    for (const PathVariant variant : {PathVariant::persistent, PathVariant::wavefront}) {
      CAPTURE(shape != nullptr, to_string(variant));
      const RenderSettings settings{variant, KernelKind::specialised, Strategy::mis};
      const PathScene start = lit_scene(0.0, shape);
      const int frames = 4;
      MovingPathRenderer gpu(start, Backend::gpu, k_detail, shape);
      run_frames(gpu, frames, 5, settings);
      CHECK(gpu.non_finite() == 0);
      MovingPathRenderer cpu(start, Backend::cpu, k_detail, shape);
      run_frames(cpu, frames, 5, settings);
      const std::vector<Vec3f> moved = gpu.vertices();
      CHECK(worst_distance(moved, cpu.vertices()) < 2e-5f);
      PathScene later = lit_scene(time_of(frames), shape);
      CHECK(worst_distance(moved, later.mesh.vertices) < 2e-5f);
      later.mesh.vertices = moved;
      const std::vector<float4> reference = fresh_sums(later, Backend::cpu, 5, settings);
      REQUIRE(pixel_statistics(cpu.mean_radiance()).mean > 0.1); // lit
      CHECK(same_sums(gpu.sums(), reference));
      CHECK(gpu.samples() == 5);
    }
  }
}
