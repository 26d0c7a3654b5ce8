// Output files: a failed write never destroys what was at the path, every write and close is
// checked (/dev/full), devices and pipes are written directly and never removed, and the
// limits on image sizes and the progress lines of long CPU work.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

#include "rt_catch.h"

#include "rt/cli.h"
#include "rt/cpu_progress.h"
#include "rt/error.h"
#include "rt/image.h"
#include "rt/launch.h"
#include "rt/output_file.h"
#include "rt/report.h"
#include "run_program.h"

using namespace rt;
namespace fs = std::filesystem;
using rt::testing::contains;

namespace {

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

auto writes(const std::string& text) {
  return [text](std::FILE* file) { std::fwrite(text.data(), 1, text.size(), file); };
}

// Files in `folder` other than `keep`: what a failed write might have left behind.
int other_files(const fs::path& folder, const fs::path& keep) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(folder)) count += entry.path() != keep;
  return count;
}

std::string output_error(const std::function<void()>& write) {
  try {
    write();
  } catch (const OutputError& e) {
    return e.what();
  }
  return "no error";
}

Image small_image() {
  Image image(4, 3);
  for (Rgba8& p : image.pixels) p = {10, 20, 30, 255};
  return image;
}

bool is_character_device(const char* path) {
  struct stat s {};
  return ::stat(path, &s) == 0 && S_ISCHR(s.st_mode);
}

} // namespace

TEST_CASE("an output file is written whole, and replaces the old one keeping its mode",
          "[common]") {
  const fs::path folder = rt::testing::temp_folder("rt_output_whole");
  const fs::path path = folder / "out.txt";
  fs::remove(path);
  write_output_file(path.string(), "text", writes("first"));
  CHECK(contents(path) == "first");
  fs::permissions(path, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  write_output_file(path.string(), "text", writes("second, longer"));
  CHECK(contents(path) == "second, longer");
  CHECK((fs::status(path).permissions() & fs::perms::mask) ==
        (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read));
  CHECK(other_files(folder, path) == 0); // no temporary file left beside it
}

TEST_CASE("a failed write leaves the old file as it was, and nothing beside it", "[common]") {
  const fs::path folder = rt::testing::temp_folder("rt_output_failed");
  const fs::path path = folder / "keep.txt";
  write_text(path, "precious");
  // The writer writes half its data and fails, as an encoder out of memory would.
  CHECK_THROWS_AS(write_output_file(path.string(), "text",
                                    [](std::FILE* file) {
                                      std::fputs("half", file);
                                      throw OutputError("the encoder failed");
                                    }),
                  OutputError);
  CHECK(contents(path) == "precious");
  CHECK(other_files(folder, path) == 0);
}

TEST_CASE("a directory, a missing folder or an empty name is refused, and nothing removed",
          "[common]") {
  const fs::path folder = rt::testing::temp_folder("rt_output_dir");
  const fs::path directory = folder / "a_directory";
  fs::create_directories(directory);
  CHECK_THAT(
      output_error([&] { write_output_file(directory.string(), "hit file", writes("x")); }),
      contains(directory.string() + ": cannot write hit file (it is a directory)"));
  CHECK(fs::is_directory(directory));
  CHECK_THROWS_AS(check_output_path(directory.string(), "PNG"), OutputError);
  CHECK_THAT(
      output_error([&] { check_output_path((folder / "no/such/x.png").string(), "PNG"); }),
      contains("does not exist"));
  CHECK_THAT(output_error([&] { check_output_path("", "JSON report"); }),
             contains("no file name given"));
  // check_image_path refuses before any work is done, as the programs call it first.
  fs::create_directories(folder / "picture.png");
  CHECK_THAT(output_error([&] { check_image_path((folder / "picture.png").string()); }),
             contains("it is a directory"));
  CHECK_THROWS_AS(check_image_path((folder / "no/such/x.png").string()), OutputError);
}

TEST_CASE("a write-protected file is refused and kept", "[common]") {
  const fs::path folder = rt::testing::temp_folder("rt_output_protected");
  const fs::path path = folder / "protected.txt";
  fs::remove(path);
  write_text(path, "read only");
  fs::permissions(path, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  if (::geteuid() != 0) {
    CHECK_THAT(output_error([&] { write_output_file(path.string(), "text", writes("x")); }),
               contains("write-protected"));
    CHECK(contents(path) == "read only");
  } else {
    // Root may write any file, as open() would let it; the mode survives the replacement.
    write_output_file(path.string(), "text", writes("root wrote"));
    CHECK(contents(path) == "root wrote");
    CHECK((fs::status(path).permissions() & fs::perms::mask) ==
          (fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read));
  }
  fs::permissions(path, fs::perms::owner_all);
}

TEST_CASE("a symbolic link stays a link, and the file it names is replaced", "[common]") {
  const fs::path folder = rt::testing::temp_folder("rt_output_link");
  const fs::path target = folder / "target.txt", link = folder / "link.txt";
  fs::remove(link);
  write_text(target, "old");
  fs::create_symlink(target, link);
  write_output_file(link.string(), "text", writes("new"));
  CHECK(fs::is_symlink(link));
  CHECK(contents(target) == "new");
  fs::remove(link);
  fs::create_symlink(folder / "missing.txt", link);
  CHECK_THAT(output_error([&] { write_output_file(link.string(), "text", writes("x")); }),
             contains("symbolic link to nothing"));
  CHECK(fs::is_symlink(link));
  fs::remove(link);
}

TEST_CASE("devices are written directly and never removed, and /dev/full is an error",
          "[common]") {
  REQUIRE(is_character_device("/dev/null"));
  write_output_file("/dev/null", "text", writes("gone"));
  CHECK(is_character_device("/dev/null"));
  if (!is_character_device("/dev/full")) return; // not every system has it
  // Every writer the course has: raw bytes, PNG, PFM, the JSON report, all onto a full disk.
  CHECK_THAT(output_error([] {
               write_output_file("/dev/full", "hit file", writes(std::string(1 << 16, 'x')));
             }),
             contains("/dev/full: cannot write hit file (No space left on device)"));
  CHECK_THAT(output_error([] { write_png("/dev/full", small_image()); }),
             contains("/dev/full: cannot write PNG (No space left on device)"));
  CHECK_THAT(output_error([] {
               const std::vector<Vec3f> rgb(12);
               write_pfm("/dev/full", 4, 3, rgb);
             }),
             contains("No space left on device"));
  Report report("title", "Mrays/s", "reference");
  report.add_row({"a row", "cpu", 1.0, 2.0, "0 px differ", {}});
  CHECK_THAT(output_error([&] { report.write_json("/dev/full"); }),
             contains("/dev/full: cannot write JSON report"));
  CHECK(is_character_device("/dev/full"));
}

TEST_CASE("a named pipe is written directly and stays a pipe", "[common]") {
  const fs::path folder = rt::testing::temp_folder("rt_output_fifo");
  const fs::path fifo = folder / "pipe";
  fs::remove(fifo);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  std::string received;
  std::thread reader([&] { received = contents(fifo); });
  write_output_file(fifo.string(), "text", writes("through the pipe"));
  reader.join();
  CHECK(received == "through the pipe");
  CHECK(fs::is_fifo(fifo));
  fs::remove(fifo);
}

TEST_CASE("the image size limit: a side and the pixels in all", "[common]") {
  const auto parse = [](const std::string& width, const std::string& height) {
    CLI::App app;
    CommonOptions options;
    add_common_options(app, options);
    const std::string name = "program";
    std::vector<const char*> argv{name.c_str(), "--width", width.c_str(), "--height",
                                  height.c_str()};
    app.parse(static_cast<int>(argv.size()), const_cast<char**>(argv.data()));
    return options.extent().pixel_count();
  };
  CHECK(parse("7680", "4320") == 7680LL * 4320); // 8K UHD
  CHECK(parse("16384", "2048") == k_max_image_pixels);
  CHECK_THROWS_AS(parse("16384", "2049"), CLI::ValidationError);
  CHECK_THROWS_AS(parse("16385", "1"), CLI::ValidationError);
}

TEST_CASE("long CPU work prints its name, how far it has come, and when it is done",
          "[common]") {
  std::ostringstream out;
  {
    const CpuWorkName name("float64 reference");
    CpuProgress progress(720, "rows", out, std::chrono::milliseconds(0));
    progress.update(360);
  }
  const std::string text = out.str();
  CHECK_THAT(text, rt::testing::starts_with("float64 reference: 50% (360 of 720 rows), "));
  CHECK_THAT(text, contains("float64 reference: done in "));
  // Work shorter than its period prints nothing; a quiet caller silences it.
  std::ostringstream none;
  {
    CpuProgress progress(10, "rays", none, std::chrono::hours(1));
    progress.update(5);
  }
  {
    const QuietCpuProgress quiet;
    CpuProgress progress(10, "rays", none, std::chrono::milliseconds(0));
    progress.update(5);
  }
  CHECK(none.str().empty());
  // Without a name, the line says what kind of work it is.
  std::ostringstream unnamed;
  {
    CpuProgress progress(4, nullptr, unnamed, std::chrono::milliseconds(0));
    progress.update(1);
  }
  CHECK_THAT(unnamed.str(), rt::testing::starts_with("working on the CPU: 25%, "));
}

TEST_CASE("the CPU launch helper still runs every pixel exactly once", "[common]") {
  const Extent extent{37, 23};
  std::vector<std::atomic<int>> count(static_cast<std::size_t>(extent.pixel_count()));
  for_each_pixel_cpu(extent, [&](int x, int y) { ++count[y * extent.width + x]; });
  for (const auto& c : count) CHECK(c.load() == 1);
}

TEST_CASE("under an OutputStaging nothing is replaced until commit, and nothing at all without",
          "[common]") {
  const fs::path folder = rt::testing::temp_folder("rt_output_staged");
  const fs::path image = folder / "keep.png", report = folder / "keep.json";
  write_text(image, "old image");
  write_text(report, "old report");
  {
    OutputStaging staging;
    write_output_file(image.string(), "image", writes("new image"));
    CHECK(contents(image) == "old image"); // written whole beside it, not yet in place
    CHECK_THROWS_AS(write_output_file("/dev/full", "report", writes(std::string(1 << 16, 'x'))),
                    OutputError);
  } // the run failed: no commit
  CHECK(contents(image) == "old image");
  CHECK(other_files(folder, image) == 1); // the report, and no temporary file left

  {
    OutputStaging staging;
    write_output_file(image.string(), "image", writes("first"));
    write_output_file(report.string(), "report", writes("new report"));
    write_output_file(image.string(), "image", writes("second"));
    {
      const UnstagedWrites now;
      write_output_file((folder / "shot.png").string(), "screenshot", writes("now"));
    }
    CHECK(contents(folder / "shot.png") == "now");
    CHECK(contents(image) == "old image");
    staging.commit();
  }
  CHECK(contents(image) == "second"); // written twice: the later bytes
  CHECK(contents(report) == "new report");
  CHECK(other_files(folder, image) == 2); // report and screenshot; no temporary file
  CHECK_THROWS_AS(
      [] {
        OutputStaging one;
        OutputStaging two;
      }(),
      Error);
}

TEST_CASE("a report path is refused before the work when it names an image", "[common]") {
  CHECK_THROWS_AS(check_report_path("out.png"), UsageError);
  CHECK_THROWS_AS(check_report_path("OUT.EXR"), UsageError);
  CHECK_THROWS_AS(check_report_path("/nonexistent-dir/report.json"), OutputError);
  CHECK_NOTHROW(check_report_path("report.json"));
  CHECK_NOTHROW(check_report_path("/dev/stdout"));
}
