// Chapter 07 tests of bad input that must neither destroy data nor give a wrong answer: ray
// files beyond the supported range (both sides of each bound), a bad first ray in a file of
// the largest accepted size refused without reading the rest, rays inside the range that hit
// tiny and huge triangles as the float64 reference does, the automatic framing at the edge of
// the range, and the program's --hits, --output and --json onto a directory, a full disk and
// a write-protected file, which it must refuse without removing them.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

#include "rt_catch.h"

#include "run_program.h"

#include "bvh_build.h"
#include "bvh_trace.h"
#include "protocol.h"
#include "ray_io.h"
#include "rt/error.h"
#include "shade.h"
#include "supported_range.h"

using namespace rt;
using namespace rt::ch07;
using rt::testing::contains;
using rt::testing::line_count;
using rt::testing::ProgramRun;

namespace {

constexpr float k_inf = std::numeric_limits<float>::infinity();

ProgramRun run_program(const std::string& arguments) {
  return rt::testing::run_command(std::string(RT_CH07_PROGRAM) + " --headless --backend cpu " +
                                  arguments);
}

const std::string k_room = RT_ASSETS_DIR "/cornell_room.obj.gz";

std::string input_error(const std::function<void()>& read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

std::string ray_error(const RayF& ray) {
  const RayF good{{0, 0, 0}, {0, 0, 1}};
  const std::vector<RayF> rays{good, ray};
  return input_error(
      [&] { parse_ray_bytes(std::as_bytes(std::span<const RayF>(rays)), "rays.bin"); });
}

// Resets this process's peak resident memory (VmHWM) to its present size; false where the
// kernel does not offer that.
bool reset_peak_memory() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

// A field of /proc/self/status in KiB, or -1.
long long status_kib(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind(field + ":", 0) == 0) return std::stoll(line.substr(field.size() + 1));
  return -1;
}

void write_bytes(const std::string& path, const void* data, std::size_t bytes) {
  std::ofstream(path, std::ios::binary)
      .write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
}

bool is_character_device(const char* path) {
  struct stat s {};
  return ::stat(path, &s) == 0 && S_ISCHR(s.st_mode);
}

ch04::Mesh one_triangle(Vec3f a, Vec3f b, Vec3f c) {
  ch04::Mesh mesh;
  mesh.vertices = {a, b, c};
  mesh.triangles = {{0, 1, 2}};
  return mesh;
}

} // namespace

TEST_CASE("ray files: origins up to 1e10, and not beyond", "[ch07]") {
  CHECK(ray_error({{0, 0, -1e10f}, {0, 0, 1}}) == "no error");
  CHECK(ray_error({{1e10f, -1e10f, 1e10f}, {1, 0, 0}}) == "no error");
  CHECK_THAT(ray_error({{0, 0, -1.01e10f}, {0, 0, 1}}),
             contains("rays.bin: ray 1: the origin (0, 0, -1.00999997e+10) lies beyond the "
                      "supported +-1e+10"));
}

TEST_CASE("ray files: directions whose largest component lies in [1e-4, 1e4]", "[ch07]") {
  CHECK(ray_error({{0, 0, 0}, {1e-4f, 0, 0}}) == "no error");
  CHECK(ray_error({{0, 0, 0}, {-1e4f, 5e3f, 1e-30f}}) == "no error");
  CHECK_THAT(ray_error({{0, 0, 0}, {0, 0.9e-4f, 0}}),
             contains("ray 1: the direction (0, 9.00000014e-05, 0) is outside the supported "
                      "lengths: its largest component must lie in [0.0001, 10000]"));
  CHECK_THAT(ray_error({{0, 0, 0}, {0, 0, -1.1e4f}}), contains("is outside the supported"));
  CHECK_THAT(ray_error({{0, 0, 0}, {0x1p-149f, 0, 0}}), contains("is outside the supported"));
}

TEST_CASE("ray files: the bytes in memory read as the file does", "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07_input");
  const std::string path = (folder / "same.rays").string();
  const std::vector<RayF> rays = {{{1, 2, 3}, {0, 0, -1}}, {{-5e9f, 0, 0}, {1e-4f, 1e4f, 0}}};
  write_ray_file(path, rays);
  const std::vector<RayF> from_file = read_ray_file(path);
  const std::vector<RayF> from_bytes =
      parse_ray_bytes(std::as_bytes(std::span<const RayF>(rays)), "memory");
  REQUIRE(from_file.size() == 2);
  REQUIRE(from_bytes.size() == 2);
  CHECK(std::memcmp(from_file.data(), from_bytes.data(), sizeof(RayF) * 2) == 0);
  CHECK(std::memcmp(from_file.data(), rays.data(), sizeof(RayF) * 2) == 0);
  CHECK_THAT(input_error([] { read_ray_file(""); }), contains("is empty"));
}

TEST_CASE("a bad first ray in a file of the largest accepted size is refused at once",
          "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07_input");
  const std::string path = (folder / "largest.rays").string();
  // A sparse file of exactly k_default_max_records rays (1 GiB), whose first ray has a NaN.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float first[8] = {nan, 0, 0, 0, 0, 1, 0, 1};
  write_bytes(path, first, sizeof first);
  std::filesystem::resize_file(path, k_default_max_records * sizeof(RayF));
  const bool measurable = reset_peak_memory();
  if (!measurable) WARN("no /proc/self/clear_refs here: the memory the read takes is unknown");
  const long long before = status_kib("VmRSS");
  CHECK_THAT(input_error([&] { read_ray_file(path); }),
             contains("largest.rays: ray 0: the origin (nan, 0, 0) is not finite"));
  const long long peak = status_kib("VmHWM");
  std::filesystem::remove(path);
  // Reading the whole file first would have taken 1 GiB; one 1 MiB chunk is all it needs.
  if (measurable && before >= 0 && peak >= 0) CHECK(peak - before < 64 * 1024);
  // One ray more than the limit is refused by the size alone.
  write_bytes(path, first, sizeof first);
  std::filesystem::resize_file(path, (k_default_max_records + 1) * sizeof(RayF));
  CHECK_THAT(input_error([&] { read_ray_file(path); }),
             contains("33554433 rays is more than the limit of 33554432"));
  std::filesystem::remove(path);
}

TEST_CASE("rays inside the range hit tiny and huge triangles as the float64 reference does",
          "[ch07]") {
  struct Case {
    float size;        // the triangle's legs
    float distance;    // from the ray's origin to the triangle's plane
    float direction_z; // the ray's direction (0, 0, -direction_z)
  };
  for (const Case c :
       {Case{1e-10f, 1e-10f, 1.0f}, Case{1e-10f, 1.0f, 1e-4f}, Case{2e9f, 8e9f, 1.0f},
        Case{2e9f, 8e9f, 1e-4f}, Case{2e9f, 8e9f, 1e4f}}) {
    CAPTURE(c.size, c.distance, c.direction_z);
    const ch04::Mesh mesh = one_triangle({0, 0, 0}, {c.size, 0, 0}, {0, c.size, 0});
    const Bvh bvh = build_bvh(mesh, BuildOptions{});
    // Rays aimed at points all over the triangle's interior, from in front of it.
    std::vector<RayF> rays;
    for (int i = 1; i < 8; ++i)
      for (int j = 1; i + j < 8; ++j)
        rays.push_back(
            {{c.size * i / 8.0f, c.size * j / 8.0f, c.distance}, {0, 0, -c.direction_z}});
    const std::vector<MeshHit> hits =
        trace_rays(Backend::cpu, Query::closest, ch04::TriangleVariant::watertight, bvh, rays);
    const ch04::MeshView view = ch04::host_view(mesh);
    for (std::size_t k = 0; k < rays.size(); ++k) {
      const ch06::SurfaceHit<double> reference =
          ch06::closest_surface(view, ch03::ray_as<double>(rays[k]));
      CAPTURE(k);
      REQUIRE(reference.triangle == 0);
      CHECK(hits[k].triangle == 0);
      CHECK(std::isfinite(hits[k].t));
      CHECK(std::abs(double(hits[k].t) - reference.t) <= 1e-6 * reference.t);
    }
  }
}

TEST_CASE("auto-frame names a scene whose camera would stand beyond the range", "[ch07]") {
  Aabb edge;
  edge.grow(Vec3f{-1e10f, -1e10f, -1e10f});
  edge.grow(Vec3f{1e10f, 1e10f, 1e10f});
  CHECK_THAT(input_error([&] { auto_frame_view(edge); }),
             contains("auto-frame: a camera that frames the scene") &&
                 contains("beyond the supported +-1e+10"));
  Aabb inside;
  inside.grow(Vec3f{-1e9f, -1e9f, -1e9f});
  inside.grow(Vec3f{1e9f, 1e9f, 1e9f});
  const ProtocolView view = auto_frame_view(inside);
  CHECK_NOTHROW(make_protocol_camera(view, 64, 48));
}

TEST_CASE("program: a failed write removes nothing that was there", "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07_input");
  const std::string rays = (folder / "rays.bin").string();
  write_ray_file(rays, std::vector<RayF>{{{0, 1, 0.5f}, {0, 0, -1}}});
  const std::string scene = " --scene " + k_room + " --rays " + rays + " --hits ";

  // --hits onto a directory: refused, and the directory (with what is in it) stays.
  const std::filesystem::path directory = folder / "a_directory";
  std::filesystem::create_directories(directory);
  std::ofstream(directory / "inside.txt") << "kept";
  ProgramRun run = run_program(scene + directory.string());
  INFO(run.output);
  CHECK(run.exit_code == 1);
  CHECK(line_count(run.output) == 1);
  CHECK_THAT(run.output, contains("it is a directory"));
  CHECK(std::filesystem::exists(directory / "inside.txt"));

  // A ray file that fails to load writes nothing: an old hit file stays as it was.
  const std::string old_hits = (folder / "old_hits.bin").string();
  std::ofstream(old_hits) << "old hits";
  const std::string bad_rays = (folder / "bad.bin").string();
  std::ofstream(bad_rays) << std::string(31, 'x');
  run = run_program(" --scene " + k_room + " --rays " + bad_rays + " --hits " + old_hits);
  CHECK(run.exit_code == 1);
  std::ifstream kept(old_hits);
  std::string text;
  std::getline(kept, text);
  CHECK(text == "old hits");

  // A write-protected hit file is refused and kept (root may write it, as open() would).
  if (::geteuid() != 0) {
    std::filesystem::permissions(old_hits, std::filesystem::perms::owner_read);
    run = run_program(scene + old_hits);
    CHECK(run.exit_code == 1);
    CHECK_THAT(run.output, contains("write-protected"));
    CHECK(std::filesystem::file_size(old_hits) == 8);
    std::filesystem::permissions(old_hits, std::filesystem::perms::owner_all);
  }

  // Onto devices: /dev/null takes the hits; /dev/full fails, and stays a device.
  run = run_program(scene + "/dev/null");
  CHECK(run.exit_code == 0);
  CHECK(is_character_device("/dev/null"));
  if (is_character_device("/dev/full")) {
    run = run_program(scene + "/dev/full");
    CHECK(run.exit_code == 1);
    CHECK(line_count(run.output) == 1);
    CHECK_THAT(run.output, contains("/dev/full: cannot write hit file (No space left"));
    CHECK(is_character_device("/dev/full"));
    // A PNG onto a full disk: an error, never "wrote", and the link to the device stays.
    const std::filesystem::path full_png = folder / "full.png";
    std::filesystem::remove(full_png);
    std::filesystem::create_symlink("/dev/full", full_png);
    run = run_program("--scene " + k_room + " --image-only --width 32 --height 24 --output " +
                      full_png.string());
    CHECK(run.exit_code == 1);
    CHECK_THAT(run.output, contains("cannot write PNG (No space left on device)"));
    CHECK_FALSE(contains("wrote").match(run.output));
    CHECK(std::filesystem::is_symlink(full_png));
    CHECK(is_character_device("/dev/full"));
  }
}

TEST_CASE("program: rays beyond the supported range are refused in one line", "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07_input");
  const std::string rays = (folder / "far.bin").string();
  write_ray_file(rays,
                 std::vector<RayF>{{{0, 1, 0.5f}, {0, 0, -1}}, {{2e10f, 0, 0}, {1, 0, 0}}});
  const ProgramRun run = run_program("--scene " + k_room + " --rays " + rays + " --hits " +
                                     (folder / "hits.bin").string());
  INFO(run.output);
  CHECK(run.exit_code == 1);
  CHECK(line_count(run.output) == 1);
  CHECK_THAT(run.output, contains("ray 1: the origin") && contains("+-1e+10"));
}

#ifdef RT_CH07_EMBREE_PROGRAM
TEST_CASE("the Embree comparison takes --backend cpu, not its value as a scene", "[ch07]") {
  const std::string program = RT_CH07_EMBREE_PROGRAM;
  ProgramRun run = rt::testing::run_command(program + " --backend gpu " + k_room);
  CHECK(run.exit_code == 2);
  CHECK(line_count(run.output) == 1);
  CHECK_THAT(run.output, contains("--backend"));
  run = rt::testing::run_command(program + " --backend cpu missing.obj");
  CHECK(run.exit_code != 0);
  CHECK(line_count(run.output) == 1);
  CHECK_THAT(run.output, contains("missing.obj"));
  CHECK_FALSE(contains("cpu").match(run.output));
}
#endif

TEST_CASE("the help sentence names the ray-file limits and range", "[ch07]") {
  CHECK_THAT(describe_ray_file_limits(), contains("at most 33554432 rays") &&
                                             contains("+-1e+10") &&
                                             contains("[0.0001, 10000]"));
}
