// Chapter 09 tests of ch09_embree_compare, where Embree is installed: the wide trees trace the
// room's rays as Embree does (a differing triangle only ever at the same distance, no hit that
// one finds and the other misses), and a --tracer or --threads it cannot honour, or a --json
// it cannot write, is one error line and a non-zero exit before any ray is traced.
#ifdef RT_CH09_EMBREE_PROGRAM

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "rt_catch.h"

#include "run_program.h"

namespace {

using rt::testing::contains;
using rt::testing::line_count;
using rt::testing::ProgramRun;

const std::string k_program = RT_CH09_EMBREE_PROGRAM;
const std::string k_room = RT_ASSETS_DIR "/cornell_room.obj.gz";

} // namespace

TEST_CASE("embree compare: the wide trees hit what Embree hits, up to ties", "[ch09]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch09_embree");
  // The default (the CPU's own tree), others, and trees built with spatial splits.
  const std::pair<std::string, std::string> cases[] = {{"", ""},
                                                       {"wide8", ""},
                                                       {"cwbvh8", ""},
                                                       {"wide4_packed_sorted", ""},
                                                       {"", " --split sbvh --split-budget 0.5"},
                                                       {"wide8", " --split sbvh"}};
  int k = 0;
  for (const auto& [tracer, split] : cases) {
    CAPTURE(tracer, split);
    const std::string json = (folder / ("report" + std::to_string(k++) + ".json")).string();
    const std::string choice = (tracer.empty() ? "" : " --tracer " + tracer) + split;
    const ProgramRun run = rt::testing::run_command(
        k_program + choice + " --width 48 --height 27 --runs 1 --json " + json + " " + k_room);
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    CHECK_THAT(run.output, contains("Our " + (tracer.empty() ? "cpu8" : tracer) + " tree"));
    if (!split.empty()) CHECK_THAT(run.output, contains("spatial splits"));
    CHECK_THAT(run.output, contains("| diffuse |"));

    std::ifstream in(json);
    const nlohmann::json report = nlohmann::json::parse(in);
    int compared = 0;
    for (const auto& row : report.at("rows")) {
      const std::string variant = row.at("variant").get<std::string>();
      if (!variant.ends_with(", ours") || variant.find(", build") != std::string::npos)
        continue;
      CAPTURE(variant);
      const auto& m = row.at("metrics");
      CHECK(m.at("rays").get<double>() > 0.0);
      CHECK(m.at("only_ours_hits").get<double>() == 0.0);
      CHECK(m.at("only_embree_hits").get<double>() == 0.0);
      // Closest hits: a differing triangle is a tie at the same t. (Any hit compares only
      // "hit or not", whose differences are the two counts above.)
      if (variant.find(", ao,") == std::string::npos)
        CHECK(m.at("differ").get<double>() == m.at("same_t").get<double>());
      ++compared;
    }
    CHECK(compared == 3); // primary, ao, diffuse
  }
}

TEST_CASE("embree compare: an unknown tracer, another thread count or an absurd image is "
          "refused",
          "[ch09]") {
  ProgramRun run = rt::testing::run_command(k_program + " --tracer wide16 " + k_room);
  CHECK(run.exit_code == 2);
  CHECK(line_count(run.output) == 1);
  CHECK_THAT(run.output, contains("--tracer wide16") && contains("wide8") &&
                             contains("cwbvh8_greedy") && contains("binary"));

  // A split budget without spatial splits, and a split the program does not know.
  run = rt::testing::run_command(k_program + " --split-budget 0.5 " + k_room);
  CHECK(run.exit_code == 2);
  CHECK(line_count(run.output) == 1);
  CHECK_THAT(run.output, contains("--split-budget goes with --split sbvh"));
  run = rt::testing::run_command(k_program + " --split median " + k_room);
  CHECK(run.exit_code != 0);
  CHECK_THAT(run.output, contains("--split"));

  // Both tracers run on the CPU backend's threads, which RT_CPU_THREADS sets.
  run = rt::testing::run_command("RT_CPU_THREADS=1 " + k_program + " --threads 2 " + k_room);
  CHECK(run.exit_code == 2);
  CHECK(line_count(run.output) == 1);
  CHECK_THAT(run.output, contains("RT_CPU_THREADS=2"));

  // A side within the limit, a total beyond it: refused before a ray is made.
  run = rt::testing::run_command(k_program + " --width 16384 --height 16384 " + k_room);
  CHECK(run.exit_code == 2);
  CHECK(line_count(run.output) == 1);
  CHECK_THAT(run.output, contains("268435456 pixels"));
}

TEST_CASE("embree compare: a --json it cannot write is refused before the comparison",
          "[ch09]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch09_embree");
  const ProgramRun run = rt::testing::run_command(
      k_program + " --width 16 --height 9 --runs 1 --json " +
      (folder / "no" / "such" / "report.json").string() + " " + k_room);
  INFO(run.output);
  CHECK(run.exit_code == 1);
  CHECK(line_count(run.output) == 1); // no table: nothing was traced
  CHECK_THAT(run.output, contains("report.json"));
}

#endif
