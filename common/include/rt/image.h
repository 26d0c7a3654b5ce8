// Images (chapter 01): 8-bit RGBA pixels as the kernels write them, and the two file formats
// the course writes: PNG (through stb_image_write) and PFM (32-bit float, for exact values).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rt/hd.h"
#include "rt/vec.h"

namespace rt {

struct Rgba8 {
  std::uint8_t r = 0, g = 0, b = 0, a = 0; // 4 bytes: one 32-bit store per pixel

  RT_HD friend constexpr bool operator==(Rgba8 p, Rgba8 q) {
    return p.r == q.r && p.g == q.g && p.b == q.b && p.a == q.a;
  }
};
static_assert(sizeof(Rgba8) == 4);

struct Image {
  int width = 0;
  int height = 0;
  std::vector<Rgba8> pixels; // row-major, row 0 at the top

  Image() = default;
  Image(int w, int h) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h) {}
  Rgba8& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const Rgba8& at(int x, int y) const {
    return pixels[static_cast<std::size_t>(y) * width + x];
  }
};

// Writes an 8-bit PNG; throws OutputError naming the path if it cannot. Like every output,
// through write_output_file (rt/output_file.h): a failure leaves the path as it was.
void write_png(const std::string& path, const Image& image);
// Writes a PFM (little-endian, bottom row first as the format defines); throws OutputError.
void write_pfm(const std::string& path, int width, int height, std::span<const Vec3f> rgb);
// PNG or PFM by the path's extension (.png / .pfm); other extensions are a UsageError.
void write_image(const std::string& path, const Image& image);
// Throws UsageError unless the path ends in .png or .pfm, and OutputError when it can never
// be written (rt/output_file.h: a directory, a folder that does not exist...), so that a
// program can refuse it before its work instead of after.
void check_image_path(const std::string& path);

// How many pixels differ between two images of the same size.
std::size_t count_differing_pixels(std::span<const Rgba8> a, std::span<const Rgba8> b);

} // namespace rt
