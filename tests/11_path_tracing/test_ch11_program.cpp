// Chapter 11 tests of the program itself on the CPU: a headless run reports its three kernels
// with the same sums and writes the PNG and the PFM; --convergence writes JSON rows whose
// error falls with the samples; bad input ends in one error line and a non-zero exit.
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "rt_catch.h"

#include "run_program.h"

namespace {

using rt::testing::contains;
using rt::testing::ProgramRun;

const rt::testing::HeadlessCpuProgram run_program(RT_CH11_PROGRAM);

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

} // namespace

TEST_CASE("program: three kernels, the same sums, an image and its radiance", "[ch11]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch11");
  const std::string image = (folder / "room.png").string(),
                    pfm = (folder / "room.pfm").string();
  const ProgramRun run = run_program("--width 32 --height 24 --spp 4 --frames 1 --output " +
                                     image + " --pfm " + pfm);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("megakernel, mis (specialised)"));
  CHECK_THAT(run.output, contains("megakernel, mis, all features"));
  CHECK_THAT(run.output, contains("persistent, mis (specialised)"));
  CHECK_THAT(run.output, contains("wavefront, mis (specialised)"));
  CHECK_THAT(run.output, contains("features: emitters"));
  CHECK_THAT(run.output, !contains("NaN/Inf samples dropped"));
  CHECK_THAT(run.output, contains(" 0 px differ from it"));
  CHECK_THAT(run.output, contains("kernels: specialised on emitters"));
  CHECK(std::filesystem::file_size(image) > 100);
  CHECK(std::filesystem::file_size(pfm) > 32 * 24 * 12);
}

TEST_CASE("program: --convergence rows fall with the samples, for every strategy", "[ch11]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch11");
  const std::string json = (folder / "convergence.json").string();
  const ProgramRun run = run_program("--convergence --width 24 --height 16 --spp 16 "
                                     "--reference-spp 256 --json " +
                                     json);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  std::ifstream in(json);
  const nlohmann::json report = nlohmann::json::parse(in);
  std::map<std::string, std::map<int, double>> rel_mse; // variant -> samples -> error
  for (const auto& row : report.at("rows")) {
    const auto& metrics = row.at("metrics");
    const std::string variant = row.at("variant").get<std::string>();
    const int samples = static_cast<int>(metrics.at("samples").get<double>());
    rel_mse[variant.substr(0, variant.rfind(','))][samples] =
        metrics.at("rel_mse").get<double>();
    CHECK(metrics.at("non_finite").get<double>() == 0.0);
    CHECK(metrics.at("wall_ms").get<double>() > 0.0);
  }
  REQUIRE(rel_mse.size() == 5);
  for (const auto& [variant, errors] : rel_mse) {
    CAPTURE(variant);
    REQUIRE(errors.size() == 5);                // 1, 2, 4, 8, 16
    CHECK(errors.at(16) < 0.35 * errors.at(1)); // 1/16 expected; a wide margin for noise
  }
  CHECK(rel_mse.at("persistent, mis").at(16) < rel_mse.at("persistent, bsdf").at(16));
}

TEST_CASE("program: --seconds renders until the time is up", "[ch11]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch11");
  const std::string pfm = (folder / "timed.pfm").string();
  const ProgramRun run = run_program("--width 16 --height 12 --seconds 0.2 --image-only "
                                     "--output " +
                                     (folder / "timed.png").string() + " --pfm " + pfm);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK(std::filesystem::file_size(pfm) > 16 * 12 * 12);
}

TEST_CASE("program: a missing MTL file gives the default material", "[ch11]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch11");
  write_text(folder / "no_mtl.obj", "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                    "usemtl light\nf 1 2 3\n");
  const ProgramRun run = run_program("--scene " + (folder / "no_mtl.obj").string() +
                                     " --width 16 --height 12 --spp 1 --frames 1 --output " +
                                     (folder / "no_mtl.png").string());
  INFO(run.output);
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.output, contains("1 triangle without a material"));
  CHECK_THAT(run.output, contains("features: sky"));
}

TEST_CASE("program: bad input is refused with one line", "[ch11]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch11");
  write_text(folder / "negative.mtl", "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 -2 1\n");
  write_text(folder / "negative.obj",
             "mtllib negative.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n");
  write_text(folder / "flat.mtl", "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 1 1\n");
  write_text(folder / "flat.obj", "mtllib flat.mtl\nv 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\n"
                                  "f 1 2 4\nusemtl lamp\nf 1 2 3\n");
  const rt::testing::RefusedInput cases[] = {
      {"--spp 0", 2, "--spp"},
      {"--width 100000", 2, "width"},
      {"--seconds -1", 2, "--seconds"},
      {"--strategy best", 2, "unknown strategy 'best'"},
      {"--variant fastest", 2, "unknown variant 'fastest'"},
      {"--scene " + (folder / "missing.obj").string(), 2, "missing.obj"},
      {"--scene " + (folder / "negative.obj").string(), 1, "negative emission"},
      {"--scene " + (folder / "flat.obj").string(), 1, "zero area"},
      {"--moving --scene " + std::string(RT_ASSETS_DIR "/cornell_room.obj.gz"), 2,
       "not with --scene"},
      {"--moving --convergence", 2, "not with --scene or --convergence"},
      {"--detail 64", 2, "--detail goes with --moving"},
      {"--moving --detail 4", 2, "--detail"},
  };
  rt::testing::check_refused(run_program, cases);
}

TEST_CASE("program: --moving renders frames of chapter 10's scene, its tree built each frame",
          "[ch11]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch11");
  const std::string image = (folder / "moving.png").string();
  const ProgramRun run = run_program("--moving --detail 16 --frames 3 --width 24 --height 16 "
                                     "--spp 2 --sun 0.4,1,0.3 --output " +
                                     image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("chapter 10's moving scene"));
  CHECK_THAT(run.output, contains("moving: tree every frame"));
  CHECK_THAT(run.output, contains("over 3 frames; 0 NaN/Inf samples"));
  CHECK(std::filesystem::file_size(image) > 100);
}
