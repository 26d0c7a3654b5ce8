// Chapter 08 tests of the program itself on the CPU: the report traces every path the CPU has
// and says each gives chapter 07's hits (in the text and in the JSON), the benchmark mode on a
// small scene, and bad input (GPU-only paths on the CPU, unknown paths, bad options, flags that
// do nothing in the mode asked for) ending in one error line and a non-zero exit.
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "rt_catch.h"

#include "07_bvh/program_cases.h"
#include "run_program.h"

namespace {

using rt::testing::ProgramRun;

const rt::testing::HeadlessCpuProgram run_program(RT_CH08_PROGRAM);

const std::string k_room = RT_ASSETS_DIR "/cornell_room.obj.gz";

} // namespace

TEST_CASE("program: the report traces the CPU's paths, each with chapter 07's hits", "[ch08]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch08");
  const std::string json = (folder / "report.json").string();
  const std::string image = (folder / "room.png").string();
  const ProgramRun run = run_program("--scene " + k_room +
                                     " --width 64 --height 36 --frames 1 --reference-rays 64 "
                                     "--json " +
                                     json + " --output " + image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  for (const char* type : {"primary", "ao", "diffuse"})
    for (const char* path : {"global", "float4"})
      CHECK_THAT(run.output, rt::testing::contains(std::string("cornell_room, ") + type + ", " +
                                                   path + "  "));
  CHECK_THAT(run.output, !rt::testing::contains("differ from chapter 07"));
  CHECK_THAT(run.output, rt::testing::contains("ids differ from float64"));
  CHECK(std::filesystem::file_size(image) > 100);

  std::ifstream in(json);
  const nlohmann::json report = nlohmann::json::parse(in);
  int rows = 0;
  for (const auto& row : report.at("rows")) {
    CAPTURE(row.at("variant").get<std::string>());
    CHECK(row.at("backend") == "cpu");
    CHECK(row.at("metrics").at("differing_from_ch07").get<double>() == 0.0);
    CHECK(row.at("metrics").at("mrays_per_s").get<double>() > 0.0);
    ++rows;
  }
  CHECK(rows == 6); // 3 ray types x the CPU's 2 paths
}

TEST_CASE("program: --memory narrows the paths measured", "[ch08]") {
  const ProgramRun run = run_program("--scene " + k_room +
                                     " --width 32 --height 18 --frames 1 --reference-rays 16 "
                                     "--memory float4 --output ''");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, rt::testing::contains("cornell_room, primary, float4"));
  CHECK_THAT(run.output, !rt::testing::contains("cornell_room, primary, global"));
}

TEST_CASE("program: the benchmark mode on a small scene", "[ch08]") {
  const ProgramRun run =
      run_program("--benchmark " + k_room + " --width 48 --height 27 --frames 1");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, rt::testing::contains("| cornell_room |"));
  CHECK_THAT(run.output, rt::testing::contains("diffuse rays, Mrays/s"));
  CHECK_THAT(run.output, !rt::testing::contains("DIFFERS"));
}

TEST_CASE("program: bad input gives one error line and a non-zero exit", "[ch08]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch08");
  const rt::testing::RefusedInput cases[] = {
      {"--memory texture --scene " + k_room, 2, "needs the GPU"},
      {"--memory global,ldg --scene " + k_room, 2, "'ldg' needs the GPU"},
      {"--benchmark --memory float4_ldg " + k_room, 2, "needs the GPU"},
      {"--memory textures", 2, "unknown memory path 'textures'"},
      {"--memory global,,float4", 2, "unknown memory path ''"},
      {"--reference-rays 0", 2, "reference-rays"},
      {"--scene " + (folder / "missing.obj").string(), 2, "missing.obj"},
      {"--benchmark --models " + (folder / "nothing").string(), 1, "benchmark set"},
      {k_room, 2, "--benchmark"},
      {"--image-only --output ''", 2, "--output"},
  };
  rt::testing::check_refused(run_program, cases);
}

TEST_CASE("program: a flag that does nothing in the mode asked for is refused", "[ch08]") {
  const rt::testing::QueryCommandLines q = rt::testing::query_command_lines("rt_ch08", k_room);
  const rt::testing::RefusedInput cases[] = {
      {q.bench + " --reference-rays 8", 2, "--reference-rays does nothing with --benchmark"},
      {q.bench + " --skip-cpu", 2, "--skip-cpu does nothing with --benchmark"},
      {q.bench + " --output " + q.image, 2, "--output does nothing with --benchmark"},
      {q.bench + " --fov 30", 2, "--fov does nothing with --benchmark"},
      {"--benchmark --scene " + k_room + " --models " + q.folder.string(), 2,
       "--scene does nothing with --benchmark"},
      {q.ray_query + " --json " + q.json, 2, "--json does nothing with --rays"},
      {q.ray_query + " --reference-rays 8", 2, "--reference-rays does nothing with --rays"},
      {q.ray_query + " --height 8", 2, "--height does nothing with --rays"},
      {q.dump + " --camera orthographic", 2, "--camera does nothing with --dump-hits"},
      {q.dump + " --image-only", 2, "--image-only does nothing with --dump-hits"},
      {"--image-only --memory float4 --output " + q.image, 2,
       "--memory does nothing with --image-only"},
      {"--image-only --skip-cpu --output " + q.image, 2,
       "--skip-cpu does nothing with --image-only"},
  };
  rt::testing::check_refused(run_program, cases);
  const rt::testing::RefusedInput window_cases[] = {
      {q.bench, 2, "--window does nothing with --benchmark"},
      {q.ray_query, 2, "--window does nothing with --rays"},
      {"--memory float4", 2, "--memory does nothing with --window"},
      {"--reference-rays 8", 2, "--reference-rays does nothing with --window"},
  };
  rt::testing::check_refused_with_window(RT_CH08_PROGRAM, window_cases);
}
