// Chapter 07: ray files and hit files. See ray_io.h.
#include "ray_io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <system_error>

#include "rt/error.h"
#include "rt/output_file.h"
#include "supported_range.h"

namespace rt::ch07 {

namespace {

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError(path + ": " + what);
}

std::string format_float(float x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", static_cast<double>(x));
  return text;
}

// A bound as the messages name it: 1e+10, 0.0001.
std::string short_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", static_cast<double>(static_cast<float>(x)));
  return text;
}

std::string format_vec(Vec3f v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.9g, %.9g, %.9g)", static_cast<double>(v.x),
                static_cast<double>(v.y), static_cast<double>(v.z));
  return text;
}

bool all_finite(Vec3f v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Records are read and checked a chunk at a time, so that a bad record is refused as soon as
// it arrives, not after gigabytes that come before it were read: 1 MiB of records per chunk.
constexpr std::size_t k_chunk_bytes = 1 << 20;

// Checks a stream of `count` records of type Record from `source`, which fills a span and
// returns how many records it delivered, and returns them. problem(record) names what is
// wrong with a record, or is empty.
template <class Record, class Source, class Problem>
std::vector<Record> read_checked(const std::string& name, std::uintmax_t count, Source source,
                                 Problem problem) {
  std::vector<Record> records;
  records.reserve(static_cast<std::size_t>(count)); // address space only: pages fill as read
  const std::size_t chunk = k_chunk_bytes / sizeof(Record);
  while (records.size() < count) {
    const std::size_t first = records.size();
    records.resize(first + std::min<std::size_t>(chunk, count - first));
    const std::size_t got = source(std::span<Record>(records).subspan(first));
    if (got != records.size() - first) fail(name, "the file changed size while it was read");
    for (std::size_t k = first; k < records.size(); ++k) {
      const std::string what = problem(records[k]);
      if (!what.empty())
        fail(name, std::string(problem.noun) + " " + std::to_string(k) + ": " + what);
    }
  }
  return records;
}

// How many records of type Record a file or a block of bytes holds, after checking its size:
// a whole number of records, no more than max_records. Nothing is read or allocated before.
template <class Record>
std::uintmax_t record_count(const std::string& name, std::uintmax_t bytes,
                            long long max_records, const char* noun) {
  if (bytes % sizeof(Record) != 0)
    fail(name, std::to_string(bytes) + " bytes is not a whole number of " +
                   std::to_string(sizeof(Record)) + "-byte " + noun);
  const std::uintmax_t count = bytes / sizeof(Record);
  if (count > static_cast<std::uintmax_t>(std::max(max_records, 0LL)))
    fail(name, std::to_string(count) + " " + noun + " is more than the limit of " +
                   std::to_string(max_records));
  return count;
}

// Reads a file of records, checked as above. The size the file system reports is checked
// first, so that a huge or ragged file fails before anything is read; the reads then must
// deliver exactly that many bytes (a file can change while it is read).
template <class Record, class Problem>
std::vector<Record> read_records(const std::string& path, long long max_records,
                                 const char* noun, Problem problem) {
  namespace fs = std::filesystem;
  if (path.empty()) throw InputError("the file name of the " + std::string(noun) + " is empty");
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error) fail(path, "cannot open (" + error.message() + ")");
  if (fs::is_directory(status))
    fail(path, "is a directory, not a file of " + std::string(noun));
  if (!fs::is_regular_file(status)) fail(path, "is not a regular file");
  const std::uintmax_t bytes = fs::file_size(path, error);
  if (error) fail(path, "cannot read its size (" + error.message() + ")");
  const std::uintmax_t count = record_count<Record>(path, bytes, max_records, noun);

  errno = 0;
  const File file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  std::vector<Record> records = read_checked<Record>(
      path, count,
      [&](std::span<Record> into) {
        const std::size_t got =
            std::fread(into.data(), sizeof(Record), into.size(), file.get());
        if (std::ferror(file.get()))
          fail(path, std::string("read error (") + std::strerror(errno) + ")");
        return got;
      },
      problem);
  if (std::fgetc(file.get()) != EOF) fail(path, "the file changed size while it was read");
  return records;
}

// The same from bytes in memory: copied record by record (the bytes need not be aligned).
template <class Record, class Problem>
std::vector<Record> parse_records(std::span<const std::byte> bytes, const std::string& name,
                                  long long max_records, const char* noun, Problem problem) {
  const std::uintmax_t count = record_count<Record>(name, bytes.size(), max_records, noun);
  std::size_t offset = 0;
  return read_checked<Record>(
      name, count,
      [&](std::span<Record> into) {
        std::memcpy(into.data(), bytes.data() + offset, into.size_bytes());
        offset += into.size_bytes();
        return into.size();
      },
      problem);
}

// Why a ray cannot be traced, or an empty string. NaN anywhere poisons every slab test and
// triangle test it reaches; a zero direction has no line to follow. Beyond those, the ray must
// lie in the range the float pipeline supports (chapter 03's supported_range.h): its origin
// within +-k_max_coordinate, and its direction's largest component within
// [k_min_direction, k_max_direction], since t and the triangle test's products scale with
// 1 / |direction|.
struct RayProblem {
  const char* noun = "ray";
  std::string operator()(const RayF& ray) const {
    if (!all_finite(ray.origin))
      return "the origin " + format_vec(ray.origin) + " is not finite";
    if (!all_finite(ray.direction))
      return "the direction " + format_vec(ray.direction) + " is not finite";
    if (ray.direction == Vec3f{}) return "the direction is zero";
    if (!std::isfinite(ray.tmin)) return "tmin (" + format_float(ray.tmin) + ") is not finite";
    if (std::isnan(ray.tmax)) return "tmax is NaN";
    if (max_component(elementwise_abs(ray.origin)) > ch03::k_max_coordinate)
      return "the origin " + format_vec(ray.origin) + " lies beyond the supported +-" +
             short_number(ch03::k_max_coordinate);
    const float largest = max_component(elementwise_abs(ray.direction));
    if (largest < k_min_direction || largest > k_max_direction)
      return "the direction " + format_vec(ray.direction) +
             " is outside the supported lengths: its largest component must lie in [" +
             short_number(k_min_direction) + ", " + short_number(k_max_direction) + "]";
    return {};
  }
};

struct HitProblem {
  const char* noun = "record";
  std::string operator()(const MeshHit& hit) const {
    if (std::isnan(hit.t)) return "t is NaN";
    if (hit.triangle < -1)
      return "triangle id " + std::to_string(hit.triangle) + " is below -1";
    const bool infinite = hit.t == std::numeric_limits<float>::infinity();
    if (infinite != (hit.triangle == -1))
      return "t " + format_float(hit.t) + " with triangle id " + std::to_string(hit.triangle) +
             " is neither a hit nor a miss (t = +inf, id = -1)";
    return {};
  }
};

template <class Record>
void write_records(const std::string& path, std::span<const Record> records, const char* what) {
  write_output_file(path, what, [&](std::FILE* file) {
    // An empty span may hold a null pointer, which fwrite must not get even for 0 bytes.
    if (!records.empty()) std::fwrite(records.data(), sizeof(Record), records.size(), file);
  });
}

} // namespace

std::string describe_ray_file_limits() {
  return "Ray files hold at most " + std::to_string(k_default_max_records) +
         " rays; origins within +-" + short_number(ch03::k_max_coordinate) +
         ", directions of any length whose largest component lies in [" +
         short_number(k_min_direction) + ", " + short_number(k_max_direction) +
         "] (book chapter 07).";
}

std::vector<RayF> read_ray_file(const std::string& path, long long max_rays) {
  return read_records<RayF>(path, max_rays, "rays", RayProblem{});
}

std::vector<RayF> parse_ray_bytes(std::span<const std::byte> bytes,
                                  const std::string& name_for_errors, long long max_rays) {
  return parse_records<RayF>(bytes, name_for_errors, max_rays, "rays", RayProblem{});
}

void write_ray_file(const std::string& path, std::span<const RayF> rays) {
  write_records(path, rays, "ray file");
}

std::vector<MeshHit> read_hit_file(const std::string& path, long long max_hits) {
  return read_records<MeshHit>(path, max_hits, "hit records", HitProblem{});
}

void write_hit_file(const std::string& path, std::span<const MeshHit> hits) {
  write_records(path, hits, "hit file");
}

} // namespace rt::ch07
