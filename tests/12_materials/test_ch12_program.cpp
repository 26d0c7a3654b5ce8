// Chapter 12 tests of the program itself on the CPU: a headless run of the material room
// reports chapter 11's kernels with the same sums, chapter 11's tracer on the same geometry,
// the texture filters with their aliasing and the compensation; the built-in furnace and
// series scenes render; a .pfm holds the radiance; flags the run would not read and bad input
// end in one error line and a non-zero exit.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "rt_catch.h"

#include "image_files.h"
#include "run_program.h"

namespace {

using rt::testing::contains;
using rt::testing::ProgramRun;
namespace fs = std::filesystem;

const rt::testing::HeadlessCpuProgram run_program(RT_CH12_PROGRAM);

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

} // namespace

TEST_CASE("program: the material room, its kernels, chapter 11's tracer and the textures",
          "[ch12]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch12");
  const std::string image = (folder / "room.png").string();
  const std::string json = (folder / "room.json").string();
  const ProgramRun run = run_program("--width 32 --height 24 --spp 2 --frames 1 --output " +
                                     image + " --json " + json);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("megakernel, mis, sobol sampler (specialised)"));
  CHECK_THAT(run.output, contains("wavefront, mis, sobol sampler (specialised)"));
  CHECK_THAT(run.output, contains(" 0 px differ from it"));
  CHECK_THAT(run.output, contains("emitters, textures, specular"));
  CHECK_THAT(run.output, contains("chapter 11's tracer, same geometry"));
  CHECK_THAT(run.output, contains("textures: point"));
  CHECK_THAT(run.output, contains("textures: trilinear"));
  CHECK_THAT(run.output, contains("energy compensation off"));
  CHECK_THAT(run.output, !contains("NaN/Inf samples dropped"));
  CHECK_THAT(run.output, !contains("warning"));
  CHECK(fs::file_size(image) > 100);
  // Aliasing, measured: the filters' base-colour error against the supersampled reference.
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(json));
  double point = -1.0, trilinear = -1.0, heitz = -1.0, caps = -1.0;
  for (const auto& row : report["rows"]) {
    const std::string variant = row["variant"];
    if (variant == "visible normals: Heitz 2018") heitz = row["metrics"]["mean_z"];
    if (variant.rfind("visible normals: spherical caps", 0) == 0)
      caps = row["metrics"]["mean_z"];
    if (variant.rfind("textures: point", 0) == 0) point = row["metrics"]["aliasing_rmse"];
    if (variant.rfind("textures: trilinear", 0) == 0)
      trilinear = row["metrics"]["aliasing_rmse"];
  }
  CAPTURE(point, trilinear, heitz, caps);
  REQUIRE(point > 0.0);
  REQUIRE(trilinear > 0.0);
  // The two visible-normal samplers draw the same distribution: their mean normals agree.
  REQUIRE(heitz > 0.5);
  CHECK(std::abs(heitz - caps) < 0.005);
}

TEST_CASE("program: the furnace sphere is the sky, in the radiance file", "[ch12]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch12");
  const fs::path file = folder / "furnace.pfm";
  const ProgramRun run = run_program("--furnace glass --width 16 --height 12 --spp 64 "
                                     "--image-only --output " +
                                     file.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const rt::LinearImage image = rt::testing::read_pfm(file);
  double sum = 0.0;
  for (const rt::Vec3f& p : image.rgb) sum += (p.x + p.y + p.z) / 3.0;
  CHECK(sum / double(image.rgb.size()) == Approx(1.0).epsilon(0.01));
}

TEST_CASE("program: the roughness series and a glTF scene render", "[ch12]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch12");
  for (const std::string args :
       {std::string("--series gold"), std::string("--series rough-glass"),
        std::string("--scene ") + RT_ASSETS_DIR + "/material_room.obj.gz"}) {
    const ProgramRun run = run_program(args +
                                       " --width 20 --height 12 --spp 2 --image-only "
                                       "--output " +
                                       (folder / "series.png").string());
    INFO(args << "\n" << run.output);
    CHECK(run.exit_code == 0);
  }
}

TEST_CASE("program: bad input is refused with one line", "[ch12]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch12");
  write_text(folder / "draco.gltf",
             R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],)"
             R"("extensionsRequired":["KHR_draco_mesh_compression"]})");
  write_text(folder / "scene.ply", "ply\n");
  const rt::testing::RefusedInput cases[] = {
      {"--furnace unobtainium", 2, "unknown material 'unobtainium'"},
      {"--series unobtainium", 2, "unknown material"},
      {"--filter anisotropic", 2, "anisotropic"},
      {"--roughness 0.5", 2, "--roughness is the --furnace sphere's"},
      {"--furnace glass --roughness 2", 2, "--roughness"},
      {"--furnace glass --series gold", 2, "one"},
      {"--scene " + (folder / "draco.gltf").string(), 1, "KHR_draco_mesh_compression"},
      {"--scene " + (folder / "scene.ply").string(), 2, "scene.ply"},
      {"--scene " + (folder / "missing.glb").string(), 2, "missing.glb"},
      {"--furnace glass --sky 0", 2, "nothing lights the scene"},
      {"--convergence --variant wavefront", 2, "--convergence measures every variant"},
      {"--convergence --output c.png", 2, "not with --output"},
      {"--reference-spp 64", 2, "--reference-spp goes with --convergence"},
      {"--spp 4 --seconds 1", 2, "--spp and --seconds both"},
      {"--exposure 2 --output x.pfm", 2, "x.pfm holds the radiance itself"},
      {"-o \"\"", 2, "the run would write nothing"},
  };
  rt::testing::check_refused(run_program, cases);
}

TEST_CASE("program: --sampler renders the material room, and --sampler and --samplers refuse "
          "what they cannot do",
          "[ch12][samplers]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch12");
  const auto radiance = [&](const std::string& sampler) {
    const fs::path file = folder / ("sampler_" + sampler + ".pfm");
    const ProgramRun run =
        run_program("--sampler " + sampler +
                    " --width 20 --height 12 --spp 2 --image-only --output " + file.string());
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    return rt::testing::read_pfm(file).rgb;
  };
  const std::vector<rt::Vec3f> independent = radiance("independent");
  CHECK(radiance("zsobol") != independent); // the flag reaches the kernels
  // --convergence --samplers: every sampler's rows and its line in the context, chapter 11's
  // report made over chapter 12's renderer.
  const ProgramRun compared =
      run_program("--convergence --samplers --width 8 --height 6 --spp 4 --reference-spp 8");
  INFO(compared.output);
  REQUIRE(compared.exit_code == 0);
  for (const char* sampler : {"independent", "stratified", "sobol", "zsobol"}) {
    CAPTURE(sampler);
    CHECK_THAT(compared.output, contains(std::string("sampler ") + sampler + ": MSE slope"));
  }
  CHECK_THAT(compared.output, contains("persistent, mis, zsobol sampler, 4 spp"));
  const rt::testing::RefusedInput cases[] = {
      {"--sampler bogus", 2, "unknown sampler 'bogus'"},
      {"--samplers", 2, "--samplers goes with --convergence"},
      {"--convergence --sampler sobol", 2, "not with --sampler"},
  };
  rt::testing::check_refused(run_program, cases);
}
