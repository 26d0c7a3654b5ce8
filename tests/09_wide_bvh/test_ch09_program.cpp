// Chapter 09 tests of the program itself on the CPU: the report measures every tracer on
// every ray type and finds chapter 07's hits (in the text and the JSON), --tracer narrows it,
// the benchmark mode on a small scene (its report stating the runs --frames asked for), ray
// files (also through the sorted rays' tracer) and hit dumps through the compressed tree give
// brute force's hits, and bad input (a flag that does nothing in the mode asked for among it)
// ends in one error line and a non-zero exit.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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

const rt::testing::HeadlessCpuProgram run_program(RT_CH09_PROGRAM);

const std::string k_room = RT_ASSETS_DIR "/cornell_room.obj.gz";

} // namespace

TEST_CASE("program: the report measures every tracer, each with chapter 07's hits", "[ch09]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch09");
  const std::string json = (folder / "report.json").string();
  const std::string image = (folder / "room.png").string();
  const ProgramRun run = run_program("--scene " + k_room +
                                     " --width 64 --height 36 --frames 1 --reference-rays 64 "
                                     "--json " +
                                     json + " --output " + image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  for (const char* type : {"primary", "ao", "diffuse"})
    for (const char* tracer :
         {"binary (ch07)", "wide4", "wide8", "cwbvh8", "cwbvh8 greedy", "wide4 packed",
          "wide4 packed, shared stack", "wide4 packed, persistent", "wide4 packed, sorted rays",
          "wide4 packed, tiles", "wide4 packed, persistent, tiles", "cpu8"})
      CHECK_THAT(run.output,
                 contains(std::string("cornell_room, ") + type + ", " + tracer + "  "));
  CHECK_THAT(run.output, contains("cornell_room, build cwbvh8 (CPU)"));
  CHECK_THAT(run.output, !contains("disagree"));
  CHECK_THAT(run.output, contains("diffuse rays, Mrays/s"));
  CHECK(std::filesystem::file_size(image) > 100);

  std::ifstream in(json);
  const nlohmann::json report = nlohmann::json::parse(in);
  int traced = 0, builds = 0;
  for (const auto& row : report.at("rows")) {
    const std::string variant = row.at("variant").get<std::string>();
    CAPTURE(variant);
    CHECK(row.at("backend") == "cpu");
    if (variant.find(", build ") != std::string::npos) {
      CHECK(row.at("metrics").at("bytes_per_triangle").get<double>() > 0.0);
      ++builds;
      continue;
    }
    CHECK(row.at("metrics").at("differing_from_ch07").get<double>() == 0.0);
    CHECK(row.at("metrics").at("mrays_per_s").get<double>() > 0.0);
    ++traced;
  }
  CHECK(traced == 36); // 3 ray types x 12 tracers
  CHECK(builds == 6);  // the wide trees: the variants of wide4 packed share its tree
}

TEST_CASE("program: --tracer narrows the tracers measured", "[ch09]") {
  const ProgramRun run = run_program("--scene " + k_room +
                                     " --width 32 --height 18 --frames 1 --reference-rays 16 "
                                     "--tracer cwbvh8_greedy --output ''");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("cornell_room, primary, cwbvh8 greedy"));
  CHECK_THAT(run.output, contains("cornell_room, primary, binary (ch07)"));
  CHECK_THAT(run.output, !contains("cornell_room, primary, wide8"));
}

TEST_CASE("program: the benchmark mode on a small scene", "[ch09]") {
  const ProgramRun run =
      run_program("--benchmark " + k_room + " --width 48 --height 27 --frames 1");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("| cornell_room |"));
  CHECK_THAT(run.output, contains("diffuse rays, Mrays/s"));
  CHECK_THAT(run.output, contains("cwbvh8 greedy"));
  CHECK_THAT(run.output, !contains("DIFFERS"));
}

TEST_CASE("program: ray files and hit dumps through the compressed tree", "[ch09]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch09");
  const ch04::Mesh mesh = ch05::load_obj(k_room).geometry;
  std::vector<RayF> rays = rt::testing::room_ray_fan(500);
  rays.push_back({{0.0f, 100.0f, 0.5f}, {0.0f, 1.0f, 0.0f}}); // away from it all
  const std::string ray_file = (folder / "rays.bin").string();
  const std::string hit_file = (folder / "hits.bin").string();
  write_ray_file(ray_file, rays);
  for (const char* tracer : {"cwbvh8", "wide4", "binary", "wide4_packed_sorted"}) {
    CAPTURE(tracer);
    const std::vector<MeshHit> hits =
        rt::testing::hits_from_program(run_program, "--scene " + k_room + " --tracer " + tracer,
                                       ray_file, hit_file, rays.size());
    const HitAgreement a = compare_hits(
        hits, ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, rays));
    CHECK(a.mismatches == 0);
    CHECK(a.hits > 400);
    CHECK(hits.back().triangle == -1);
  }

  // The protocol's diffuse rays from inside the room, dumped through the compressed tree.
  const std::string primary = (folder / "primary.bin").string();
  const std::string diffuse = (folder / "diffuse.bin").string();
  const std::string view =
      " --width 64 --height 48 --eye 0,1,0.9 --target 0,0.8,-1 --fov 70 --scene " + k_room;
  REQUIRE(run_program("--dump-hits " + primary + view).exit_code == 0);
  REQUIRE(run_program("--dump-hits " + diffuse + " --ray-type diffuse" + view).exit_code == 0);
  const PinholeCamera camera =
      make_protocol_camera({0.0f, 1.0f, 0.9f}, {0.0f, 0.8f, -1.0f}, 70.0f, 64, 48);
  const std::vector<RayF> camera_rays = camera_rays_cpu(camera);
  const auto brute =
      ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, camera_rays);
  CHECK(compare_hits(read_hit_file(primary), brute).mismatches == 0);
  ch07::Aabb bounds;
  for (const Vec3f& v : mesh.vertices) bounds.grow(v);
  const SecondaryRays secondary =
      secondary_rays_cpu(RayType::diffuse, mesh, brute, camera, scene_radius(bounds));
  const auto expected = scatter_to_pixels(
      ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, secondary.rays),
      secondary.pixel, 64 * 48);
  const HitAgreement a = compare_hits(read_hit_file(diffuse), expected);
  CHECK(a.mismatches == 0);
  CHECK(a.hits == 64 * 48); // inside a closed room every diffuse ray hits a wall
}

TEST_CASE("program: bad input gives one error line and a non-zero exit", "[ch09]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch09");
  const std::string hits = (folder / "hits.bin").string();
  const rt::testing::RefusedInput cases[] = {
      {"--tracer cwbvh16", 2, "the tracers are binary, wide4, wide8, cwbvh8, cwbvh8_greedy"},
      {"--reference-rays 0", 2, "reference-rays"},
      {"--scene " + (folder / "missing.obj").string(), 2, "missing.obj"},
      {"--benchmark --models " + (folder / "nothing").string(), 1, "benchmark set"},
      {k_room, 2, "--benchmark"},
      {"--hits " + hits, 2, "--rays"},
      {"--rays " + (folder / "missing.bin").string() + " --hits " + hits, 1, "missing.bin"},
      {"--ray-type shiny --dump-hits " + hits, 2, "ray-type"},
      {"--image-only --output ''", 2, "--output"},
      {"--heat-map --image-only --output " + (folder / "counts.exr").string(), 2,
       "--heat-map draws node counts"},
      {"--heat-map --benchmark " + k_room, 2, "--heat-map does nothing with --benchmark"},
  };
  rt::testing::check_refused(run_program, cases);
}

TEST_CASE("program: --heat-map draws the wide nodes each ray visits", "[ch09]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch09");
  const std::string image = (folder / "heat.png").string();
  const ProgramRun run = run_program("--heat-map --image-only --width 32 "
                                     "--height 18 --output " +
                                     image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK(std::filesystem::file_size(image) > 100);
}

TEST_CASE("program: the benchmark's report states the runs --frames asked for", "[ch09]") {
  for (const int frames : {1, 3}) {
    CAPTURE(frames);
    const ProgramRun run =
        run_program("--benchmark " + k_room +
                    " --width 16 --height 9 --tracer wide8 --frames " + std::to_string(frames));
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    CHECK_THAT(run.output,
               contains("timing: median of " + std::to_string(frames) + " after 1 warm-up"));
  }
}

TEST_CASE("program: a flag that does nothing in the mode asked for is refused", "[ch09]") {
  const rt::testing::QueryCommandLines q = rt::testing::query_command_lines("rt_ch09", k_room);
  const rt::testing::RefusedInput cases[] = {
      {q.ray_query + " --output " + q.image, 2, "--output does nothing with --rays"},
      {q.ray_query + " -o " + q.image, 2, "--output does nothing with --rays"},
      {q.ray_query + " --image-only", 2, "--image-only does nothing with --rays"},
      {q.ray_query + " --reference-rays 8", 2, "--reference-rays does nothing with --rays"},
      {q.ray_query + " --json " + q.json, 2, "--json does nothing with --rays"},
      {q.dump + " --json " + q.json, 2, "--json does nothing with --dump-hits"},
      {q.dump + " --camera orthographic", 2, "--camera does nothing with --dump-hits"},
      {q.bench + " --reference-rays 8", 2, "--reference-rays does nothing with --benchmark"},
      {q.bench + " --image-only", 2, "--image-only does nothing with --benchmark"},
      {q.bench + " --target 0,0,0", 2, "--target does nothing with --benchmark"},
      {"--benchmark --scene " + k_room + " --models " + q.folder.string(), 2,
       "--scene does nothing with --benchmark"},
      {"--image-only --tracer wide8 --output " + q.image, 2,
       "--tracer does nothing with --image-only"},
  };
  rt::testing::check_refused(run_program, cases);
  const rt::testing::RefusedInput window_cases[] = {
      {q.bench, 2, "--window does nothing with --benchmark"},
      {q.dump, 2, "--window does nothing with --dump-hits"},
      {"--tracer wide8", 2, "--tracer does nothing with --window"},
      {"--skip-cpu", 2, "--skip-cpu does nothing with --window"},
  };
  rt::testing::check_refused_with_window(RT_CH09_PROGRAM, window_cases);
}
