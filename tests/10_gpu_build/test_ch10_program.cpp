// Chapter 10 tests of the program itself on the CPU: the report builds with every builder and
// measures each tree, binary and 4-wide (chapter 09's collapse and the parallel one), with
// chapter 07's hits (in the text and the JSON);
// --builder narrows it; the benchmark mode runs on a small scene; ray files through each tree
// give brute force's hits; the moving scene writes its frames' figures and image, through the
// camera flags given; bad input ends in one error line and a non-zero exit.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rt_catch.h"

#include "07_bvh/program_cases.h"
#include "run_program.h"

#include "bvh_trace.h"
#include "obj_loader.h"
#include "ray_io.h"

using namespace rt;
using namespace rt::ch07;

namespace {

using rt::testing::contains;
using rt::testing::ProgramRun;

const rt::testing::HeadlessCpuProgram run_program(RT_CH10_PROGRAM);

const std::string k_room = RT_ASSETS_DIR "/cornell_room.obj.gz";

} // namespace

TEST_CASE("program: the report builds with every builder and measures each tree", "[ch10]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch10");
  const std::string json = (folder / "report.json").string();
  const std::string image = (folder / "room.png").string();
  const ProgramRun run =
      run_program("--scene " + k_room + " --width 64 --height 36 --frames 1 --json " + json +
                  " --output " + image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  for (const char* type : {"primary", "ao", "diffuse"})
    for (const char* tree :
         {"CPU SAH (ch07)", "LBVH", "LBVH 63-bit", "PLOC", "PLOC 4-wide",
          "LBVH 4-wide (parallel collapse)", "H-PLOC", "H-PLOC 4-wide (parallel collapse)",
          "H-PLOC + treelets", "H-PLOC + treelets 4-wide (parallel collapse)"})
      CHECK_THAT(run.output,
                 contains(std::string("cornell_room, ") + type + ", " + tree + " "));
  CHECK_THAT(
      run.output,
      contains("| builder | built on | build ms | + 4-wide collapse ms: sah / depth rule | SAH "
               "cost | depth |"));
  CHECK_THAT(run.output, !contains("disagree"));
  CHECK(std::filesystem::file_size(image) > 100);

  std::ifstream in(json);
  const nlohmann::json report = nlohmann::json::parse(in);
  int traced = 0, builds = 0;
  for (const auto& row : report.at("rows")) {
    const std::string variant = row.at("variant").get<std::string>();
    CAPTURE(variant);
    if (variant.find(", build ") != std::string::npos) {
      CHECK(row.at("metrics").at("sah_cost").get<double>() > 0.0);
      CHECK(row.at("metrics").at("depth").get<double>() <= 63.0);
      CHECK(row.at("metrics").at("collapse_ms").get<double>() > 0.0);
      CHECK(row.at("metrics").at("collapse_depth_ms").get<double>() > 0.0);
      ++builds;
      continue;
    }
    CHECK(row.at("metrics").at("differing_from_ch07").get<double>() == 0.0);
    ++traced;
  }
  CHECK(traced == 54); // 3 ray types x 6 builders x (binary, 4-wide, parallel 4-wide)
  CHECK(builds == 6);
}

TEST_CASE("program: --builder narrows the builds to it and chapter 07's", "[ch10]") {
  const ProgramRun run = run_program("--scene " + k_room +
                                     " --width 32 --height 18 --frames 1 --builder ploc "
                                     "--output ''");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("cornell_room, build PLOC"));
  CHECK_THAT(run.output, contains("cornell_room, build CPU SAH (ch07)"));
  CHECK_THAT(run.output, !contains("cornell_room, build LBVH"));
}

TEST_CASE("program: --collapse depth traces the depth rule's tree, and both are timed",
          "[ch10]") {
  const ProgramRun run = run_program("--scene " + k_room +
                                     " --width 32 --height 18 --frames 1 --builder lbvh "
                                     "--collapse depth --output ''");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("LBVH 4-wide (parallel collapse, depth rule) "));
  CHECK_THAT(run.output, !contains("LBVH 4-wide (parallel collapse) "));
  CHECK_THAT(run.output, contains("| LBVH | cpu |"));
  CHECK_THAT(run.output, !contains("disagree"));
}

TEST_CASE("program: the benchmark mode on a small scene", "[ch10]") {
  const ProgramRun run = run_program("--benchmark " + k_room +
                                     " --width 48 --height 27 --frames 1 --builder lbvh63");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("| cornell_room |"));
  CHECK_THAT(run.output, contains("diffuse rays, Mrays/s"));
  CHECK_THAT(run.output, contains("| LBVH 63-bit | cpu |"));
  CHECK_THAT(run.output, contains("| CPU SAH (ch07) | cpu |"));
  CHECK_THAT(run.output, !contains("| PLOC |"));
  CHECK_THAT(run.output, !contains("DIFFERS"));
}

TEST_CASE("program: ray files through each built tree give brute force's hits", "[ch10]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch10");
  const ch04::Mesh mesh = ch05::load_obj(k_room).geometry;
  const std::vector<RayF> rays = rt::testing::room_ray_fan(500);
  const std::string ray_file = (folder / "rays.bin").string();
  const std::string hit_file = (folder / "hits.bin").string();
  write_ray_file(ray_file, rays);
  for (const char* builder : {"lbvh", "lbvh63", "ploc", "hploc", "hploc_treelets"}) {
    CAPTURE(builder);
    const std::vector<MeshHit> hits = rt::testing::hits_from_program(
        run_program, "--scene " + k_room + " --builder " + builder, ray_file, hit_file,
        rays.size());
    const HitAgreement a = compare_hits(
        hits, ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, rays));
    CHECK(a.mismatches == 0);
    CHECK(a.hits > 400);
  }
}

TEST_CASE("program: the moving scene, rebuilt and refitted, its frames in a CSV", "[ch10]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch10");
  const std::string csv = (folder / "frames.csv").string();
  const std::string image = (folder / "moving.png").string();
  const ProgramRun run =
      run_program("--moving --frames 3 --detail 24 --width 48 --height 27 --animation-csv " +
                  csv + " --output " + image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("frame 2: rebuild "));
  CHECK_THAT(run.output, contains("LBVH, refit"));
  CHECK(std::filesystem::file_size(image) > 100);
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  CHECK(header ==
        "frame,rebuild_animate_ms,rebuild_tree_ms,rebuild_collapse_ms,"
        "rebuild_trace_ms,rebuild_wall_ms,rebuild_sah_cost,refit_animate_ms,"
        "refit_tree_ms,refit_collapse_ms,refit_trace_ms,refit_wall_ms,refit_sah_cost");
  int lines = 0;
  while (std::getline(in, line)) ++lines;
  CHECK(lines == 3);

  const ProgramRun refit =
      run_program("--moving --frames 2 --detail 16 --width 16 --height 9 --update refit "
                  "--builder ploc --output ''");
  INFO(refit.output);
  REQUIRE(refit.exit_code == 0);
  CHECK_THAT(refit.output, contains("PLOC, refit"));
  CHECK_THAT(refit.output, !contains("rebuild"));
}

TEST_CASE("program: --moving takes the camera flags and refuses what it would ignore",
          "[ch10]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch10");
  const std::string moving = "--moving --frames 1 --detail 8 --width 32 --height 18 "
                             "--update rebuild --output ";
  const auto image_of = [&](const std::string& name, const std::string& camera) {
    const std::string path = (folder / name).string();
    const ProgramRun run = run_program(moving + path + " " + camera);
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  // The animation's own camera, then each flag moving it: every image another one.
  const std::string framed = image_of("framed.png", "");
  CHECK(image_of("framed_again.png", "--eye 0,5,9.5 --target 0,-0.3,0 --fov 45") == framed);
  CHECK(image_of("eye.png", "--eye 6,2,6") != framed);
  CHECK(image_of("target.png", "--target 1,0,0") != framed);
  CHECK(image_of("fov.png", "--fov 70") != framed);
  CHECK(image_of("orthographic.png", "--camera orthographic") != framed);

  const std::string bad_obj = (folder / "broken.obj").string();
  std::ofstream(bad_obj) << "v 1 2\nf 1 2 3\n";
  const rt::testing::RefusedInput cases[] = {
      {"--moving --scene " + k_room + " --detail 40", 2, "--detail sizes the torus"},
      {"--moving --detail 3162", 2, "3161"},
      // Along the animation's view (the default camera's is another): --up is read.
      {"--moving --up 0,5.3,9.5", 2, "--up is parallel"},
      // The CSV's folder is checked before the model is loaded (and found broken).
      {"--moving --scene " + bad_obj + " --animation-csv " +
           (folder / "no" / "such.csv").string(),
       1, "such.csv"},
  };
  rt::testing::check_refused(run_program, cases);
}

TEST_CASE("program: bad input gives one error line and a non-zero exit", "[ch10]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch10");
  const std::string hits = (folder / "hits.bin").string();
  const rt::testing::RefusedInput cases[] = {
      {"--builder octree", 2, "the builders are cpu_sah, lbvh, lbvh63, ploc"},
      {"--collapse greedy", 2, "the collapse rules are sah and depth, not 'greedy'"},
      {"--update sometimes --moving", 2, "rebuild or refit"},
      {"--update refit", 2, "go with --moving"},
      {"--detail 4 --moving", 2, "--detail"},
      {"--moving --benchmark", 2, "--moving runs alone"},
      {"--scene " + (folder / "missing.obj").string(), 2, "missing.obj"},
      {"--hits " + hits, 2, "--rays"},
      {"--moving --animation-csv " + (folder / "no" / "such.csv").string(), 1, "such.csv"},
  };
  rt::testing::check_refused(run_program, cases);
}

TEST_CASE("program: a flag that does nothing in the mode asked for is refused", "[ch10]") {
  const rt::testing::QueryCommandLines q = rt::testing::query_command_lines("rt_ch10", k_room);
  const rt::testing::RefusedInput cases[] = {
      {q.bench + " --skip-cpu", 2, "--skip-cpu does nothing with --benchmark"},
      {q.bench + " --output " + q.image, 2, "--output does nothing with --benchmark"},
      {q.bench + " --up 0,0,1", 2, "--up does nothing with --benchmark"},
      {"--benchmark --scene " + k_room + " --models " + q.folder.string(), 2,
       "--scene does nothing with --benchmark"},
      {q.ray_query + " --json " + q.json, 2, "--json does nothing with --rays"},
      {q.ray_query + " --frames 2", 2, "--frames does nothing with --rays"},
      {q.dump + " --json " + q.json, 2, "--json does nothing with --dump-hits"},
      {q.dump + " --output " + q.image, 2, "--output does nothing with --dump-hits"},
      {"--image-only --builder ploc --output " + q.image, 2,
       "--builder does nothing with --image-only"},
      {"--image-only --collapse depth --output " + q.image, 2,
       "--collapse does nothing with --image-only"},
  };
  rt::testing::check_refused(run_program, cases);
  const rt::testing::RefusedInput window_cases[] = {
      {q.bench, 2, "--window does nothing with --benchmark"},
      {q.ray_query, 2, "--window does nothing with --rays"},
      {"--builder ploc", 2, "--builder does nothing with --window"},
  };
  rt::testing::check_refused_with_window(RT_CH10_PROGRAM, window_cases);
}

TEST_CASE("program: the moving scene's last frame is a picture, refused as linear radiance",
          "[ch10]") {
  const rt::testing::RefusedInput cases[] = {
      {"--moving --output last.exr", 2, "--moving writes its last frame as a picture"},
  };
  rt::testing::check_refused(run_program, cases);
}
