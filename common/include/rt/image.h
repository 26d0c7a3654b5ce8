// Images (chapter 01): 8-bit RGBA pixels as the kernels write them, linear float pixels for
// what a renderer computes, and the file formats the course writes: PNG (through
// stb_image_write) for pictures, PFM and OpenEXR (through tinyexr) for 32-bit floats.
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

// Linear RGB floats, as a renderer computes them (radiance: no tone curve, no clipping).
struct LinearImage {
  int width = 0;
  int height = 0;
  std::vector<Vec3f> rgb; // row-major, row 0 at the top
};

// Writes an 8-bit PNG; throws OutputError naming the path if it cannot. Like every output,
// through write_output_file (rt/output_file.h): a failure leaves the path as it was.
void write_png(const std::string& path, const Image& image);
// Writes a PFM (little-endian, bottom row first as the format defines); throws OutputError.
void write_pfm(const std::string& path, int width, int height, std::span<const Vec3f> rgb);
// Writes an OpenEXR file of 32-bit float R, G and B channels (ZIP compressed, through
// tinyexr); throws OutputError.
void write_exr(const std::string& path, int width, int height, std::span<const Vec3f> rgb);
// True when the path names a float format (.pfm or .exr, in any case).
bool is_linear_image_path(const std::string& path);
// The picture by the path's extension: PNG, or its 8-bit values as floats (value / 255) in a
// PFM or EXR file. Other extensions are a UsageError.
void write_image(const std::string& path, const Image& image);
// Linear values in a PFM or EXR file, by the path's extension; a .png is a UsageError (a
// picture needs a tone curve first: the chapter that computes the values chooses it).
void write_linear_image(const std::string& path, const LinearImage& image);
// Throws UsageError unless the path ends in .png, .pfm or .exr, and OutputError when it can
// never be written (rt/output_file.h: a directory, a folder that does not exist...), so that a
// program can refuse it before its work instead of after.
void check_image_path(const std::string& path);

// How many pixels differ between two images of the same size.
std::size_t count_differing_pixels(std::span<const Rgba8> a, std::span<const Rgba8> b);

} // namespace rt
