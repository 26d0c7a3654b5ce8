// Chapter 07 tests of the program itself on the CPU: ray files in and hit files out (the
// results equal brute force), the protocol's hit dumps, the benchmark mode on a small scene
// (its timing as run, a benchmark set with models missing), and bad input (malformed ray
// files, bad options, flags that do nothing in the mode asked for) ending in one error line
// and a non-zero exit.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "07_bvh/program_cases.h"
#include "run_program.h"

#include "bvh_trace.h"
#include "obj_loader.h"
#include "protocol.h"
#include "ray_io.h"

using namespace rt;
using namespace rt::ch07;

namespace {

using rt::testing::contains;
using rt::testing::ProgramRun;

const rt::testing::HeadlessCpuProgram run_program(RT_CH07_PROGRAM);

const std::string k_room = RT_ASSETS_DIR "/cornell_room.obj.gz";

} // namespace

TEST_CASE("program: a ray file in, the hits of brute force out", "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07");
  const ch04::Mesh mesh = ch05::load_obj(k_room).geometry;
  // Rays from inside the room in every direction, and a few that miss or stop short.
  std::vector<RayF> rays = rt::testing::room_ray_fan(500);
  rays.push_back({{0.0f, 1.0f, 0.5f}, {0.0f, 0.0f, 1.0f}, 0.0f, 1e-3f}); // stops short
  rays.push_back({{0.0f, 100.0f, 0.5f}, {0.0f, 1.0f, 0.0f}});            // away from it all
  const std::string ray_file = (folder / "rays.bin").string();
  const std::string hit_file = (folder / "hits.bin").string();
  write_ray_file(ray_file, rays);
  const std::vector<MeshHit> hits = rt::testing::hits_from_program(
      run_program, "--scene " + k_room, ray_file, hit_file, rays.size());
  const std::vector<MeshHit> brute =
      ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, rays);
  const HitAgreement a = compare_hits(hits, brute);
  CHECK(a.mismatches == 0);
  CHECK(a.hits > 400);
  CHECK(hits[rays.size() - 2].triangle == -1);
  CHECK(hits.back().triangle == -1);
  CHECK(std::isinf(hits.back().t));
}

TEST_CASE("program: the protocol's hit dumps", "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07");
  const ch04::Mesh mesh = ch05::load_obj(k_room).geometry;
  const std::string primary = (folder / "primary.bin").string();
  const std::string diffuse = (folder / "diffuse.bin").string();
  // From inside the closed room, so that every bounce meets a wall.
  const std::string size =
      " --width 64 --height 48 --eye 0,1,0.9 --target 0,0.8,-1 --fov 70 --scene " + k_room;
  REQUIRE(run_program("--dump-hits " + primary + size).exit_code == 0);
  REQUIRE(run_program("--dump-hits " + diffuse + " --ray-type diffuse" + size).exit_code == 0);
  const std::vector<MeshHit> primary_hits = read_hit_file(primary);
  const std::vector<MeshHit> diffuse_hits = read_hit_file(diffuse);
  REQUIRE(primary_hits.size() == 64u * 48u);
  REQUIRE(diffuse_hits.size() == 64u * 48u);
  // The same rays made here and traced by brute force give the same hits.
  ch07::Aabb bounds;
  for (const Vec3f& v : mesh.vertices) bounds.grow(v);
  const PinholeCamera camera =
      make_protocol_camera({0.0f, 1.0f, 0.9f}, {0.0f, 0.8f, -1.0f}, 70.0f, 64, 48);
  const std::vector<RayF> rays = camera_rays_cpu(camera);
  const auto brute = ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, rays);
  CHECK(compare_hits(primary_hits, brute).mismatches == 0);
  const SecondaryRays secondary =
      secondary_rays_cpu(RayType::diffuse, mesh, brute, camera, scene_radius(bounds));
  const auto brute_secondary =
      ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, secondary.rays);
  const auto expected = scatter_to_pixels(brute_secondary, secondary.pixel, 64 * 48);
  const HitAgreement a = compare_hits(diffuse_hits, expected);
  CHECK(a.mismatches == 0);
  CHECK(a.hits == 64 * 48); // inside a closed room every diffuse ray hits a wall
}

TEST_CASE("program: the benchmark mode on a small scene", "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07");
  const std::string json = (folder / "bench.json").string();
  const ProgramRun run = run_program("--benchmark " + k_room +
                                     " --width 96 --height 54 --frames 1 --json " + json);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  for (const char* row : {"cornell_room, primary", "cornell_room, ao", "cornell_room, diffuse",
                          "cornell_room, build", "cornell_room, shaded frame"})
    CHECK_THAT(run.output, rt::testing::contains(row));
  CHECK_THAT(run.output, rt::testing::contains("| cornell_room |"));
  CHECK_THAT(run.output, rt::testing::contains("0 of"));
  CHECK(std::filesystem::file_size(json) > 100);
}

TEST_CASE("program: bad input gives one error line and a non-zero exit", "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07");
  const std::string truncated = (folder / "truncated.bin").string();
  std::ofstream(truncated, std::ios::binary) << std::string(40, '\0');
  const std::string nan_rays = (folder / "nan.bin").string();
  {
    const float nan = std::nanf("");
    const float ray[8] = {0, 0, 0, 0, nan, 1, 0, 1};
    std::ofstream(nan_rays, std::ios::binary)
        .write(reinterpret_cast<const char*>(ray), sizeof ray);
  }
  const std::string hits = (folder / "out.bin").string();
  const rt::testing::RefusedInput cases[] = {
      {"--rays " + truncated + " --hits " + hits, 1, "32-byte rays"},
      {"--rays " + nan_rays + " --hits " + hits, 1, "not finite"},
      {"--rays " + (folder / "missing.bin").string() + " --hits " + hits, 1, "missing.bin"},
      {"--rays " + truncated, 2, "--hits"},
      {"--hits " + hits, 2, "--rays"},
      {"--leaf-size 0", 2, "leaf"},
      {"--leaf-size 1000", 2, "leaf"},
      {"--bins 1", 2, "bins"},
      {"--split middle", 2, "split"},
      {"--ray-type shiny --dump-hits " + hits, 2, "ray-type"},
      {"--benchmark --models " + (folder / "nothing").string(), 1, "benchmark set"},
      {k_room, 2, "--benchmark"},
      // Flags that cannot apply together are refused, not ignored.
      {"--rays " + nan_rays + " --hits " + hits + " --dump-hits " + hits, 2, "two different"},
      {"--ray-type ao", 2, "--ray-type goes with --dump-hits"},
      {"--benchmark --dump-hits " + hits + " " + k_room, 2, "--benchmark measures"},
      {"--models " + folder.string(), 2, "--models goes with --benchmark"},
      {"--image-only --json " + hits, 2, "--json"},
      // An output that cannot be written is refused before the work.
      {"--rays " + nan_rays + " --hits " + folder.string(), 1, "hits"},
      {"--dump-hits " + (folder / "no" / "such" / "dir.bin").string() + " --scene " + k_room +
           " --width 8 --height 8",
       1, "dir.bin"},
  };
  rt::testing::check_refused(run_program, cases);
}

TEST_CASE("program: the benchmark's report states the runs it timed", "[ch07]") {
  const ProgramRun run =
      run_program("--benchmark " + k_room + " --width 16 --height 9 --frames 2");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("timing: median of 2 after 1 warm-up"));
}

TEST_CASE("program: a benchmark set with models missing names them and measures the rest",
          "[ch07]") {
  const std::filesystem::path models = rt::testing::temp_folder("rt_ch07_models");
  std::filesystem::copy_file(k_room, models / "stanford-bunny.obj.gz",
                             std::filesystem::copy_options::overwrite_existing);
  const ProgramRun run = run_program("--benchmark --models " + models.string() +
                                     " --width 16 --height 9 --frames 1");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output,
             contains("warning: --benchmark: " + models.string() +
                      " holds 1 of the benchmark set's 5 scenes; measuring those, without "
                      "armadillo-100k, stanford-dragon, conference, sponza-dabrovic"));
  CHECK_THAT(run.output, contains("| stanford-bunny |"));
  CHECK_THAT(run.output, contains("scenes: the benchmark set in " + models.string() +
                                  ", without armadillo-100k"));
}

TEST_CASE("program: a flag that does nothing in the mode asked for is refused", "[ch07]") {
  const rt::testing::QueryCommandLines q = rt::testing::query_command_lines("rt_ch07", k_room);
  const rt::testing::RefusedInput cases[] = {
      {q.bench + " --output " + q.image, 2, "--output does nothing with --benchmark"},
      {q.bench + " -o " + q.image, 2, "--output does nothing with --benchmark"},
      {q.bench + " --image-only", 2, "--image-only does nothing with --benchmark"},
      {"--benchmark --scene " + k_room + " --models " + q.folder.string(), 2,
       "--scene does nothing with --benchmark"},
      {q.bench + " --eye 1,2,3", 2, "--eye does nothing with --benchmark"},
      {q.bench + " --camera orthographic", 2, "--camera does nothing with --benchmark"},
      {q.bench + " --shading flat", 2, "--shading does nothing with --benchmark"},
      {q.bench + " --heat-map", 2, "--heat-map does nothing with --benchmark"},
      {q.bench + " --reference-pixels 8", 2,
       "--reference-pixels does nothing with --benchmark"},
      {q.bench + " --skip-cpu", 2, "--skip-cpu does nothing with --benchmark"},
      {q.ray_query + " --output " + q.image, 2, "--output does nothing with --rays"},
      {q.ray_query + " --image-only", 2, "--image-only does nothing with --rays"},
      {q.ray_query + " --json " + q.json, 2, "--json does nothing with --rays"},
      {q.ray_query + " --frames 3", 2, "--frames does nothing with --rays"},
      {q.ray_query + " --width 64", 2, "--width does nothing with --rays"},
      {q.ray_query + " --eye 0,1,0.5", 2, "--eye does nothing with --rays"},
      {q.ray_query + " --shadows off", 2, "--shadows does nothing with --rays"},
      {q.dump + " --json " + q.json, 2, "--json does nothing with --dump-hits"},
      {q.dump + " --camera orthographic", 2, "--camera does nothing with --dump-hits"},
      {q.dump + " --up 0,0,1", 2, "--up does nothing with --dump-hits"},
      {q.dump + " --output " + q.image, 2, "--output does nothing with --dump-hits"},
      {q.dump + " --frames 3", 2, "--frames does nothing with --dump-hits"},
      {q.dump + " --reference-pixels 8", 2, "--reference-pixels does nothing with --dump-hits"},
      {"--image-only --variant moller-trumbore --output " + q.image, 2,
       "--variant does nothing with --image-only"},
      {"--image-only --reference-pixels 8 --output " + q.image, 2,
       "--reference-pixels does nothing with --image-only"},
      {"--check-rays 16", 2, "--check-rays goes with --benchmark"},
      {"--end-to-end off", 2, "--end-to-end goes with --benchmark"},
      {q.bench + " --models " + q.folder.string(), 2, "--models does nothing with SCENE files"},
      {"--split median --bins 8 --image-only --output " + q.image, 2,
       "--bins does nothing with --split median"},
      {"--heat-map --shading flat --image-only --output " + q.image, 2,
       "--shading does nothing with --heat-map"},
  };
  rt::testing::check_refused(run_program, cases);

  const rt::testing::RefusedInput window_cases[] = {
      {q.bench, 2, "--window does nothing with --benchmark"},
      {q.ray_query, 2, "--window does nothing with --rays"},
      {q.dump, 2, "--window does nothing with --dump-hits"},
      {"--image-only --output " + q.image, 2, "--image-only does nothing with --window"},
      {"--variant moller-trumbore", 2, "--variant does nothing with --window"},
      {"--reference-pixels 8", 2, "--reference-pixels does nothing with --window"},
  };
  rt::testing::check_refused_with_window(RT_CH07_PROGRAM, window_cases);
}

#ifdef RT_CH07_EMBREE_PROGRAM
TEST_CASE("the Embree comparison refuses a --json it cannot write before the work", "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07");
  const ProgramRun run = rt::testing::run_command(
      std::string(RT_CH07_EMBREE_PROGRAM) + " --width 16 --height 9 --runs 1 --json " +
      (folder / "no" / "such" / "report.json").string() + " " + k_room);
  INFO(run.output);
  CHECK(run.exit_code == 1);
  CHECK(rt::testing::line_count(run.output) == 1); // no table: nothing was traced
  CHECK_THAT(run.output, contains("report.json"));
}
#endif

TEST_CASE("program: the heat map is a picture of counts, refused as linear radiance",
          "[ch07]") {
  const rt::testing::RefusedInput cases[] = {
      {"--heat-map --output counts.exr", 2, "--heat-map draws node counts"},
      {"--heat-map --output counts.pfm", 2, "--heat-map draws node counts"},
  };
  rt::testing::check_refused(run_program, cases);
}
