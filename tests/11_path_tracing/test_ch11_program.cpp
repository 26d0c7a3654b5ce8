// Chapter 11 tests of the program itself on the CPU: a headless run reports its kernels with
// the same sums and writes the PNG, and the radiance itself as PFM or EXR; --convergence
// writes JSON rows whose error falls with the samples; the MTL file's values are checked and
// the loader's warnings shown; a black image, a scene without light and flags the run would
// not read are never silent; long work says how far it has come; bad input ends in one error
// line and a non-zero exit.
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "rt_catch.h"

#include "animation.h"
#include "image_files.h"
#include "path_cases.h"
#include "path_report.h"
#include "run_program.h"

namespace {

using rt::testing::contains;
using rt::testing::ProgramRun;
using rt::testing::read_exr;
using rt::testing::read_pfm;
namespace fs = std::filesystem;

const rt::testing::HeadlessCpuProgram run_program(RT_CH11_PROGRAM);

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// A scene file of one material `lamp` (the MTL text) on a quad of side 20 in the plane z = 0,
// facing +z: seen from (0, 0, 1), it fills any image.
fs::path write_quad_scene(const fs::path& folder, const std::string& name,
                          const std::string& mtl) {
  write_text(folder / (name + ".mtl"), mtl);
  write_text(folder / (name + ".obj"), "mtllib " + name +
                                           ".mtl\nv -10 -10 0\nv 10 -10 0\n"
                                           "v 10 10 0\nv -10 10 0\nusemtl lamp\nf 1 2 3 4\n");
  return folder / (name + ".obj");
}

// One triangle lying in the plane y = 0, without a material: a flat model.
fs::path write_flat_scene(const fs::path& folder) {
  write_text(folder / "flat_floor.obj", "v -1 0 -1\nv 1 0 -1\nv 0 0 1\nf 1 3 2\n");
  return folder / "flat_floor.obj";
}

const std::string k_quad_view = " --eye 0,0,1 --target 0,0,0 ";

} // namespace

TEST_CASE("program: four kernels, the same sums, and the image", "[ch11]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const std::string image = (folder / "room.png").string();
  const ProgramRun run =
      run_program("--width 32 --height 24 --spp 4 --frames 1 --output " + image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("megakernel, mis, sobol sampler (specialised)"));
  CHECK_THAT(run.output, contains("megakernel, mis, all features, sobol sampler"));
  CHECK_THAT(run.output, contains("persistent, mis, sobol sampler (specialised)"));
  CHECK_THAT(run.output, contains("wavefront, mis, sobol sampler (specialised)"));
  CHECK_THAT(run.output, contains("features: emitters"));
  CHECK_THAT(run.output, !contains("NaN/Inf samples dropped"));
  CHECK_THAT(run.output, !contains("warning"));
  CHECK_THAT(run.output, contains(" 0 px differ from it"));
  CHECK_THAT(run.output, contains("kernels: specialised on emitters"));
  CHECK(fs::file_size(image) > 100);
}

TEST_CASE("program: a .pfm and an .exr hold the mean radiance, above 1 too", "[ch11]") {
  // A lamp of albedo 0 that fills the image: every sample of every pixel is its Ke exactly
  // (the camera ray finds it; nothing is reflected), so the mean is Ke, in both files.
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const fs::path scene =
      write_quad_scene(folder, "lamp", "newmtl lamp\nKd 0 0 0\nKe 5 2 0.5\n");
  const std::string common =
      "--scene " + scene.string() + k_quad_view + "--width 8 --height 6 --spp 3 --image-only ";
  for (const char* file : {"lamp.pfm", "lamp.exr", "lamp.png"}) {
    const ProgramRun run = run_program(common + "--output " + (folder / file).string());
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
  }
  for (const rt::LinearImage& image :
       {read_pfm(folder / "lamp.pfm"), read_exr(folder / "lamp.exr")}) {
    REQUIRE(image.width == 8);
    REQUIRE(image.height == 6);
    for (const rt::Vec3f& p : image.rgb) {
      CHECK(p.x == 5.0f);
      CHECK(p.y == 2.0f);
      CHECK(p.z == 0.5f);
    }
  }
  CHECK(fs::file_size(folder / "lamp.png") > 50); // the picture, tone-mapped: clipped at 1
}

TEST_CASE("tone map: radiance too large for the curve's squares is white, never black",
          "[ch11]") {
  const float huge[] = {2e19f, 1e30f, 3e38f, std::numeric_limits<float>::infinity()};
  std::vector<float4> sums;
  for (const float r : huge) sums.push_back({r, r, r, 1.0f});
  sums.push_back({7.5f, 7.5f, 7.5f, 1.0f}); // where the curve reaches 1
  std::vector<rt::Rgba8> pixels(sums.size());
  rt::ch11::tone_map(rt::Backend::cpu, sums.data(), {int(sums.size()), 1}, 1.0f, pixels.data());
  for (const rt::Rgba8& p : pixels) {
    CHECK(p.r == 255);
    CHECK(p.g == 255);
    CHECK(p.b == 255);
  }
}

TEST_CASE("program: --convergence rows fall with the samples, for every strategy", "[ch11]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
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

TEST_CASE("program: --seconds renders until the time is up and says how many samples",
          "[ch11]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const fs::path pfm = folder / "timed.pfm";
  const ProgramRun run = run_program("--width 16 --height 12 --seconds 0.2 --image-only "
                                     "--output " +
                                     pfm.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("rendered ") && contains(" samples per pixel in "));
  CHECK(read_pfm(pfm).rgb.size() == 16 * 12);
}

TEST_CASE("image samples: passes of bounded work, each able to report, the same sums",
          "[ch11]") {
  using namespace rt::ch11;
  const PathScene room = load_path_scene(testing::k_room);
  const rt::Extent strip{64, 1}; // one row: rows alone would say nothing until the end
  const int spp = 4096;
  PathRenderer once(room, rt::Backend::cpu);
  once.restart(cornell_camera(), strip);
  once.add_samples({}, spp);
  PathRenderer passes(room, rt::Backend::cpu);
  passes.restart(cornell_camera(), strip);
  std::ostringstream lines;
  const SamplesTaken taken =
      add_image_samples(passes, {}, spp, 0.0, lines, std::chrono::milliseconds(0));
  CHECK(taken.samples == spp);
  CHECK(testing::same_sums(once.sums(), passes.sums()));
  // 64 px x 4096 samples = 4 passes of k_paths_per_pass paths: a line after each (period 0).
  const std::string text = lines.str();
  CAPTURE(text);
  CHECK(rt::testing::line_count(text) == 4 + 1); // and "done in"
  CHECK_THAT(text, contains("rendering the image: 25% (1024 of 4096 samples)"));
  CHECK_THAT(text, contains("(4096 of 4096 samples)"));
}

TEST_CASE("moving scene: a progress line counts the frames", "[ch11]") {
  using namespace rt::ch11;
  MovingPathRenderer renderer(testing::lit_moving_scene(0.0, 8), rt::Backend::cpu, 8);
  rt::Report report("moving", "Mpaths/s", "none");
  std::ostringstream lines;
  add_moving_rows(renderer, {}, rt::ch10::moving_scene_camera(), {8, 6}, 3, report, lines,
                  std::chrono::milliseconds(0));
  const std::string text = lines.str();
  CAPTURE(text);
  CHECK_THAT(text, contains("moving scene: 33% (1 of 3 frames)"));
  CHECK_THAT(text, contains("(3 of 3 frames)"));
}

TEST_CASE("program: the MTL loader's warnings reach the reader, one line each", "[ch11]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const fs::path no_mtl = folder / "no_mtl.obj";
  write_text(no_mtl, "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl light\nf 1 2 3\n");
  const std::string small = " --width 16 --height 12 --spp 1 --frames 1 --output ";
  ProgramRun run =
      run_program("--scene " + no_mtl.string() + small + (folder / "no_mtl.png").string());
  INFO(run.output);
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.output, contains("warning: " + no_mtl.string() +
                                  ": mtllib missing.mtl: no "
                                  "such file"));
  CHECK_THAT(run.output, contains("warning: " + no_mtl.string() +
                                  ": material [ 'light' ] "
                                  "not found"));
  CHECK_THAT(run.output, contains("1 triangle without a material"));
  CHECK_THAT(run.output, contains("features: sky"));

  // Kd 1 (common in exported files) is lowered to 0.99 with a word; tinyobjloader's own notes
  // on the MTL text are passed on with the file's name.
  const fs::path white =
      write_quad_scene(folder, "white", "newmtl lamp\nKd 1 1 1\nd 1\nTr 0\n");
  run = run_program("--scene " + white.string() + k_quad_view + small +
                    (folder / "white.png").string());
  INFO(run.output);
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.output, contains("warning: " + (folder / "white.mtl").string() +
                                  ": Kd above 0.99 lowered to it in 'lamp'"));
  CHECK_THAT(run.output, contains("warning: " + (folder / "white.mtl").string() +
                                  ": Both `d` and `Tr` parameters defined"));
}

TEST_CASE("program: Kd and Ke that are not a surface or a lamp are refused, naming both",
          "[ch11]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const auto scene = [&](const std::string& name, const std::string& colours) {
    return "--scene " + write_quad_scene(folder, name, "newmtl lamp\n" + colours).string();
  };
  const rt::testing::RefusedInput cases[] = {
      {scene("ke_inf", "Kd 0.5 0.5 0.5\nKe inf 1 1\n"), 1,
       "ke_inf.mtl: material 'lamp': Ke inf 1 1: not three finite numbers"},
      {scene("ke_nan", "Kd 0.5 0.5 0.5\nKe nan 1 1\n"), 1, "ke_nan.mtl: material 'lamp': Ke"},
      {scene("ke_huge", "Ke 1e400 0 0\n"), 1, "ke_huge.mtl: material 'lamp': Ke 1e400"},
      {scene("ke_one", "Ke 5\n"), 1, "ke_one.mtl: material 'lamp': Ke 5: not three"},
      {scene("ke_nan_product", "Ke 0e999 1 1\n"), 1, "not finite numbers"},
      {scene("ke_1e30", "Ke 1e30 1e30 1e30\n"), 1, "ke_1e30.mtl: material 'lamp': Ke 1e+30"},
      {scene("ke_3e38", "Ke 3e38 1 1\n"), 1, "brighter than the brightest light"},
      {scene("ke_above", "Ke 1 2000000 1\n"), 1, "brighter than the brightest light"},
      {scene("ke_negative", "Ke 1 -2 1\n"), 1, "negative emission (Ke) 1 -2 1"},
      {scene("kd_negative", "Kd 0.5 -0.5 0.5\n"), 1, "kd_negative.mtl: material 'lamp': Kd"},
      {scene("kd_above", "Kd 1.5 0.5 0.5\n"), 1, "Kd 1.5 0.5 0.5: an albedo lies in [0, 1]"},
      {scene("kd_nan", "Kd nan 0.5 0.5\n"), 1, "kd_nan.mtl: material 'lamp': Kd nan 0.5 0.5"},
  };
  rt::testing::check_refused(run_program, cases);
}

TEST_CASE("program: a black image is not silent, and the room is the room by any path",
          "[ch11]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const std::string small = " --width 16 --height 12 --spp 2 --image-only --output ";
  // The room by another spelling of its path: its own camera, the same image.
  const std::string other_path = RT_ASSETS_DIR "/../assets/./cornell_room.obj.gz";
  ProgramRun run = run_program(small + (folder / "room.pfm").string());
  REQUIRE(run.exit_code == 0);
  run = run_program("--scene " + other_path + small + (folder / "room_too.pfm").string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, !contains("warning"));
  CHECK(read_pfm(folder / "room.pfm").rgb == read_pfm(folder / "room_too.pfm").rgb);
  // From outside its closed walls no light reaches the camera: a warning says so.
  run = run_program("--scene " + other_path + " --eye 0,1,6 --target 0,1,0" + small +
                    (folder / "outside.png").string());
  INFO(run.output);
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.output, contains("warning: every pixel is black: no path reached an emitter, "
                                  "the sky or the sun"));
}

TEST_CASE("framing: a flat model is seen face-on, not edge-on", "[ch11]") {
  using namespace rt;
  using namespace rt::ch11;
  ch04::Mesh floor; // in the plane y = 0: looking down -z, only its edge
  floor.vertices = {{-1, 0, -1}, {1, 0, -1}, {0, 0, 1}};
  floor.triangles = {{0, 2, 1}};
  const CameraSpec above = frame_from_outside(floor, 40.0, {64, 48});
  CHECK(above.eye.x == above.target.x);
  CHECK(above.eye.z == above.target.z);
  CHECK(above.eye.y > above.target.y);
  CHECK(above.up == Vec3d{0, 0, -1});
  ch04::Mesh wall = floor; // in the plane x = 0
  for (Vec3f& v : wall.vertices) v = {v.y, v.z, v.x};
  const CameraSpec side = frame_from_outside(wall, 40.0, {64, 48});
  CHECK(side.eye.x > side.target.x);
  CHECK(side.eye.y == side.target.y);
  CHECK(side.eye.z == side.target.z);
  // A model with depth is framed as chapter 06 frames it.
  const ch04::Mesh ball = ch04::make_icosphere(1, {0, 0, 0}, 1.0);
  const CameraSpec down_z = ch06::frame_bounds_down_z(ch06::bounds_of(ball), 40.0, {64, 48});
  CHECK(frame_from_outside(ball, 40.0, {64, 48}).eye == down_z.eye);

  // The program: the floor under the white sky fills the middle of the image, whose radiance
  // there is its albedo 0.8 (every bounce leaves to the sky); edge-on it was the sky, 1.
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const fs::path pfm = folder / "flat.pfm";
  const ProgramRun run =
      run_program("--scene " + write_flat_scene(folder).string() +
                  " --width 16 --height 12 --spp 2 --image-only --output " + pfm.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const rt::LinearImage image = read_pfm(pfm);
  const rt::Vec3f middle = image.rgb[6 * 16 + 8];
  CHECK(middle.x == Approx(0.8f));
}

TEST_CASE("program: --sun takes any finite direction but zero, in double", "[ch11]") {
  // The flat floor under a sun alone: a direction whose float squares overflow or vanish
  // lights it as the same direction of ordinary size does.
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const std::string common = "--scene " + write_flat_scene(folder).string() +
                             " --sky 0 --width 8 --height 6 --spp 2 --image-only --output ";
  const auto render = [&](const std::string& sun, const std::string& file) {
    const ProgramRun run = run_program(common + (folder / file).string() + " --sun " + sun);
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    CHECK_THAT(run.output, !contains("warning"));
    return read_pfm(folder / file).rgb;
  };
  const std::vector<rt::Vec3f> plain = render("1,1,0", "plain.pfm");
  CHECK(plain[3 * 8 + 4].x > 0.0f);
  CHECK(render("1e300,1e300,0", "huge.pfm") == plain);
  CHECK(render("1e-300,1e-300,0", "tiny.pfm") == plain);
}

TEST_CASE("program: bad input is refused with one line", "[ch11]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  write_text(folder / "flat.mtl", "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 1 1\n");
  write_text(folder / "flat.obj", "mtllib flat.mtl\nv 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\n"
                                  "f 1 2 4\nusemtl lamp\nf 1 2 3\n");
  const std::string dark_scene = "--scene " + write_flat_scene(folder).string();
  const std::string room = RT_ASSETS_DIR "/cornell_room.obj.gz";
  const rt::testing::RefusedInput cases[] = {
      {"--spp 0", 2, "--spp"},
      {"--width 100000", 2, "width"},
      {"--seconds -1", 2, "--seconds"},
      {"--strategy best", 2, "unknown strategy 'best'"},
      {"--variant fastest", 2, "unknown variant 'fastest'"},
      {"--scene " + (folder / "missing.obj").string(), 2, "missing.obj"},
      {"--scene " + (folder / "flat.obj").string(), 1, "zero area"},
      {"--pfm room.pfm", 2, "--pfm"}, // --output room.pfm writes the radiance
      // Nothing lights the scene: refused before the work.
      {dark_scene + " --sky 0", 2, "nothing lights the scene"},
      {dark_scene + " --sky 0 --sun 0,1,0 --sun-irradiance 0", 2, "nothing lights the scene"},
      {"--moving --sky 0", 2, "nothing lights the scene: chapter 10's moving scene"},
      // A sun direction that is none.
      {"--sun 0,0,0", 2, "--sun 0,0,0: a direction needs three finite numbers"},
      {"--sun nan,1,1", 2, "--sun"},
      {"--sun inf,0,0", 2, "--sun"},
      {"--sun 1e400,0,0", 2, "--sun"},
      // Flags the run would not read.
      {"--convergence --variant wavefront", 2, "--convergence measures every variant"},
      {"--convergence --strategy bsdf", 2, "not with --strategy"},
      {"--convergence --output c.png", 2, "not with --output"},
      {"--convergence -o c.png", 2, "not with --output"},
      {"--convergence --seconds 1", 2, "not with --seconds"},
      {"--convergence --image-only", 2, "not with --image-only"},
      {"--convergence --exposure 2", 2, "not with --exposure"},
      {"--convergence --frames 3", 2, "not with --frames"},
      {"--reference-spp 64", 2, "--reference-spp goes with --convergence"},
      {"--spp 4 --seconds 1", 2, "--spp and --seconds both"},
      {"--sun-irradiance 5", 2, "--sun-irradiance is the sun's: give --sun too"},
      {"--exposure 2 --output x.pfm", 2, "x.pfm holds the radiance itself"},
      {"--exposure 2 --output x.exr --image-only", 2, "--exposure scales the tone-mapped"},
      {"-o \"\"", 2, "the run would write nothing"},
      {"--image-only -o \"\"", 2, "the run would write nothing"},
      {"--moving --scene " + room + " --detail 16", 2, "--detail sizes the torus"},
      {"--moving --convergence", 2, "--moving renders frames of a moving scene"},
      {"--detail 64", 2, "--detail goes with --moving"},
      {"--moving --detail 4", 2, "--detail"},
      {"--moving --detail 3162", 2, "--detail"}, // 10 million triangles at most
  };
  rt::testing::check_refused(run_program, cases);
  // --window opens no window before it is refused (and the harness's runs are headless).
  const ProgramRun run =
      rt::testing::run_command(std::string(RT_CH11_PROGRAM) + " --convergence --window");
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.output, contains("not with --window"));
}

TEST_CASE("program: --moving renders frames of chapter 10's scene, moved on the backend",
          "[ch11]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const std::string image = (folder / "moving.png").string();
  const ProgramRun run = run_program("--moving --detail 16 --frames 3 --width 24 --height 16 "
                                     "--spp 2 --sun 0.4,1,0.3 --output " +
                                     image);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("chapter 10's moving scene"));
  CHECK_THAT(run.output, contains("moving: tree every frame, on the backend"));
  CHECK_THAT(run.output, contains("over 3 frames; 0 NaN/Inf samples"));
  CHECK(fs::file_size(image) > 100);
}

TEST_CASE("program: --sampler chooses where the paths' numbers come from", "[ch11][samplers]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  // The image, with every kernel's sums compared: the sampler's numbers are the same in each.
  const ProgramRun run =
      run_program("--sampler sobol --width 16 --height 12 --spp 4 --frames 1 -o " +
                  (folder / "sobol.png").string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.output, contains("megakernel, mis, sobol sampler (specialised)"));
  CHECK_THAT(run.output, contains("wavefront, mis, sobol sampler (specialised)"));
  std::size_t agreeing = 0; // the first row and the three compared with it
  for (std::size_t at = run.output.find(" 0 px differ from it"); at != std::string::npos;
       at = run.output.find(" 0 px differ from it", at + 1))
    ++agreeing;
  CHECK(agreeing == 4);
  CHECK(fs::file_size(folder / "sobol.png") > 100);
  // The radiance: the sobol sampler is the program's default, the others draw other images.
  const auto radiance = [&](const std::string& sampler) {
    const fs::path file = folder / ("sampler_" + sampler + ".pfm");
    const ProgramRun r =
        run_program((sampler.empty() ? "" : "--sampler " + sampler) +
                    " --width 16 --height 12 --spp 4 --image-only --output " + file.string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    return read_pfm(file).rgb;
  };
  const std::vector<rt::Vec3f> plain = radiance("");
  CHECK(radiance("sobol") == plain);
  for (const char* sampler : {"independent", "stratified", "zsobol"}) {
    CAPTURE(sampler);
    CHECK(radiance(sampler) != plain);
  }
}

TEST_CASE("program: --sampler and --samplers refuse what they cannot do", "[ch11][samplers]") {
  const rt::testing::RefusedInput cases[] = {
      {"--sampler bogus", 2, "unknown sampler 'bogus'"},
      {"--samplers", 2, "--samplers goes with --convergence"},
      {"--samplers --spp 4", 2, "--samplers goes with --convergence"},
      {"--convergence --sampler sobol", 2, "not with --sampler"},
      {"--convergence --samplers --sampler zsobol", 2, "not with --sampler"},
  };
  rt::testing::check_refused(run_program, cases);
}

TEST_CASE("program: --convergence --samplers measures every sampler against one reference",
          "[ch11][samplers]") {
  const fs::path folder = rt::testing::temp_folder("rt_ch11");
  const std::string json = (folder / "samplers.json").string();
  const ProgramRun run = run_program("--convergence --samplers --width 24 --height 16 --spp 8 "
                                     "--reference-spp 64 --json " +
                                     json);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  std::ifstream in(json);
  const nlohmann::json report = nlohmann::json::parse(in);
  // Rows "persistent, mis, 4 spp" (the independent sampler) and "persistent, mis, sobol
  // sampler, 4 spp": the variant without its count.
  std::map<std::string, std::map<int, double>> rmse; // variant -> samples -> RMSE
  for (const auto& row : report.at("rows")) {
    const auto& metrics = row.at("metrics");
    const std::string variant = row.at("variant").get<std::string>();
    const int samples = static_cast<int>(metrics.at("samples").get<double>());
    rmse[variant.substr(0, variant.rfind(','))][samples] = metrics.at("rmse").get<double>();
    CHECK(metrics.at("non_finite").get<double>() == 0.0);
    CHECK(metrics.at("error_lowpass").get<double>() >= 0.0);
  }
  REQUIRE(rmse.size() == 4);
  for (const char* variant :
       {"persistent, mis", "persistent, mis, stratified sampler",
        "persistent, mis, sobol sampler", "persistent, mis, zsobol sampler"}) {
    CAPTURE(variant);
    REQUIRE(rmse.count(variant) == 1);
    const auto& errors = rmse.at(variant);
    REQUIRE(errors.size() == 4); // 1, 2, 4, 8
    // 1 / sqrt(8) = 0.35 expected of an independent sampler, less of the others; a wide
    // margin for the noise of one small image. (The relative MSE is noisier still: a single
    // bright sample in a dark pixel can lift it.)
    CHECK(errors.at(8) < 0.6 * errors.at(1));
  }
  const auto& context = report.at("context");
  for (const char* sampler : {"independent", "stratified", "sobol", "zsobol"}) {
    CAPTURE(sampler);
    REQUIRE(context.contains(std::string("sampler ") + sampler));
    const std::string line = context.at(std::string("sampler ") + sampler).get<std::string>();
    CHECK_THAT(line, contains("MSE slope -"));
    CHECK_THAT(line, contains("at 8 spp"));
  }
  CHECK_THAT(context.at("sampler independent").get<std::string>(),
             contains("MSE 1.000x the independent sampler's"));
}
