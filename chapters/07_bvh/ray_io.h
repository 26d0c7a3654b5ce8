// Chapter 07: ray files and hit files, the benchmark's way of exchanging work with other ray
// tracers. Both are raw little-endian float32/int32 records with no header, so any language
// reads them with one call (numpy.fromfile, fread).
#pragma once

#include <bit>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "mesh_hit.h"
#include "ray.h"

namespace rt::ch07 {

using ch03::RayF;
using ch04::MeshHit;

// A ray record is RayF as it lies in memory: origin xyz, direction xyz, tmin, tmax (32 bytes).
// A hit record is MeshHit: float32 t (+inf for a miss), int32 triangle id (-1 for a miss).
// The files are read and written by copying records whole, which is only the file format on
// a little-endian machine with these exact layouts.
static_assert(std::endian::native == std::endian::little,
              "ray and hit files are little-endian");
static_assert(sizeof(RayF) == 32 && offsetof(RayF, direction) == 12 &&
                  offsetof(RayF, tmin) == 24,
              "a ray record is origin, direction, tmin, tmax: 8 float32");
static_assert(sizeof(MeshHit) == 8 && offsetof(MeshHit, triangle) == 4,
              "a hit record is float32 t, int32 triangle");

// The most records a file may hold: 2^25 rays (1 GiB) or hit records (256 MiB), above two
// 3840x2160 frames of rays, and what a machine with a few GB can hold with a tree beside them.
inline constexpr long long k_default_max_records = 1LL << 25;

// A ray's direction need not be unit length, but its largest component must lie in this
// range: t is measured in units of the direction, and the watertight test's product for t
// grows with 1 / |direction|. With coordinates up to chapter 03's k_max_coordinate (1e10) the
// product stays below 2e36, a hundred times under float's largest value.
inline constexpr float k_min_direction = 1e-4f;
inline constexpr float k_max_direction = 1e4f;

// One sentence for a program's --help: the most records a file may hold and the rays the
// supported range allows.
std::string describe_ray_file_limits();

// Reads a ray file. Throws InputError "path: what is wrong" for a missing or unreadable file,
// a size that is not a whole number of records, more than max_rays rays, or a ray that cannot
// be traced: NaN anywhere, a non-finite origin or direction, a zero direction, a non-finite
// tmin or a NaN tmax, an origin beyond ch03::k_max_coordinate, a direction whose largest
// component lies outside [k_min_direction, k_max_direction]. tmax = +inf is the usual
// unbounded ray; tmin > tmax is a valid ray that hits nothing. The size is checked before
// anything is read, and every ray as it is read, 1 MiB at a time: a bad ray is refused without
// reading the rest of the file.
std::vector<RayF> read_ray_file(const std::string& path,
                                long long max_rays = k_default_max_records);

// The same checks on the bytes of a ray file already in memory (what the fuzzer calls);
// errors name `name_for_errors`.
std::vector<RayF> parse_ray_bytes(std::span<const std::byte> bytes,
                                  const std::string& name_for_errors,
                                  long long max_rays = k_default_max_records);

// Writes a ray file through rt::write_output_file: a failure leaves the path as it was.
// Throws OutputError naming the path if the file cannot be written completely.
void write_ray_file(const std::string& path, std::span<const RayF> rays);

// Reads a hit file. Throws InputError for a size that is not a whole number of records, more
// than max_hits records, a NaN t, an id below -1, or a record that is half a miss (t = +inf
// with an id, or id -1 with a finite t).
std::vector<MeshHit> read_hit_file(const std::string& path,
                                   long long max_hits = k_default_max_records);

// Writes a hit file like write_ray_file. Throws OutputError naming the path.
void write_hit_file(const std::string& path, std::span<const MeshHit> hits);

} // namespace rt::ch07
