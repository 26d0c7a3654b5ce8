// Chapter 07: ray files and hit files. See ray_io.h.
#include "ray_io.h"

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

std::string format_vec(Vec3f v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.9g, %.9g, %.9g)", static_cast<double>(v.x),
                static_cast<double>(v.y), static_cast<double>(v.z));
  return text;
}

bool all_finite(Vec3f v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Reads `count` records of type Record, after checking the size the file system reports. The
// size is checked first so that a huge or ragged file fails before anything is allocated; the
// read then must deliver exactly that many bytes (a file can change while it is read).
template <class Record>
std::vector<Record> read_records(const std::string& path, long long max_records,
                                 const char* noun) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error) fail(path, "cannot open (" + error.message() + ")");
  if (fs::is_directory(status))
    fail(path, "is a directory, not a file of " + std::string(noun));
  if (!fs::is_regular_file(status)) fail(path, "is not a regular file");
  const std::uintmax_t bytes = fs::file_size(path, error);
  if (error) fail(path, "cannot read its size (" + error.message() + ")");
  if (bytes % sizeof(Record) != 0)
    fail(path, std::to_string(bytes) + " bytes is not a whole number of " +
                   std::to_string(sizeof(Record)) + "-byte " + noun);
  const std::uintmax_t count = bytes / sizeof(Record);
  if (count > static_cast<std::uintmax_t>(max_records))
    fail(path, std::to_string(count) + " " + noun + " is more than the limit of " +
                   std::to_string(max_records));

  errno = 0;
  const File file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  std::vector<Record> records(static_cast<std::size_t>(count));
  const std::size_t got =
      records.empty() ? 0
                      : std::fread(records.data(), sizeof(Record), records.size(), file.get());
  if (std::ferror(file.get()))
    fail(path, std::string("read error (") + std::strerror(errno) + ")");
  if (got != records.size() || std::fgetc(file.get()) != EOF)
    fail(path, "the file changed size while it was read");
  return records;
}

// Why a ray cannot be traced, or an empty string. NaN anywhere poisons every slab test and
// triangle test it reaches; a zero direction has no line to follow.
std::string ray_problem(const RayF& ray) {
  if (!all_finite(ray.origin)) return "the origin " + format_vec(ray.origin) + " is not finite";
  if (!all_finite(ray.direction))
    return "the direction " + format_vec(ray.direction) + " is not finite";
  if (ray.direction == Vec3f{}) return "the direction is zero";
  if (!std::isfinite(ray.tmin)) return "tmin (" + format_float(ray.tmin) + ") is not finite";
  if (std::isnan(ray.tmax)) return "tmax is NaN";
  return {};
}

std::string hit_problem(const MeshHit& hit) {
  if (std::isnan(hit.t)) return "t is NaN";
  if (hit.triangle < -1) return "triangle id " + std::to_string(hit.triangle) + " is below -1";
  const bool infinite = hit.t == std::numeric_limits<float>::infinity();
  if (infinite != (hit.triangle == -1))
    return "t " + format_float(hit.t) + " with triangle id " + std::to_string(hit.triangle) +
           " is neither a hit nor a miss (t = +inf, id = -1)";
  return {};
}

template <class Record>
void write_records(const std::string& path, std::span<const Record> records) {
  errno = 0;
  File file(std::fopen(path.c_str(), "wb"), &std::fclose);
  auto fail_write = [&](int code) {
    file.reset();
    std::error_code ignored;
    std::filesystem::remove(path, ignored); // no truncated file left to be mistaken for data
    throw OutputError(path + ": cannot write (" + std::strerror(code) + ")");
  };
  if (!file) fail_write(errno);
  // An empty span may hold a null pointer, which fwrite must not get even for 0 bytes.
  if (!records.empty() &&
      std::fwrite(records.data(), sizeof(Record), records.size(), file.get()) != records.size())
    fail_write(errno);
  // fclose flushes the last buffer, so a full disk may only show here.
  if (std::fclose(file.release()) != 0) fail_write(errno);
}

} // namespace

std::vector<RayF> read_ray_file(const std::string& path, long long max_rays) {
  std::vector<RayF> rays = read_records<RayF>(path, max_rays, "rays");
  for (std::size_t k = 0; k < rays.size(); ++k) {
    const std::string problem = ray_problem(rays[k]);
    if (!problem.empty()) fail(path, "ray " + std::to_string(k) + ": " + problem);
  }
  return rays;
}

void write_ray_file(const std::string& path, std::span<const RayF> rays) {
  write_records(path, rays);
}

std::vector<MeshHit> read_hit_file(const std::string& path, long long max_hits) {
  std::vector<MeshHit> hits = read_records<MeshHit>(path, max_hits, "hit records");
  for (std::size_t k = 0; k < hits.size(); ++k) {
    const std::string problem = hit_problem(hits[k]);
    if (!problem.empty()) fail(path, "record " + std::to_string(k) + ": " + problem);
  }
  return hits;
}

void write_hit_file(const std::string& path, std::span<const MeshHit> hits) {
  write_records(path, hits);
}

} // namespace rt::ch07
