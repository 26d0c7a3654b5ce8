// Image output (chapter 01): see rt/image.h.
#include "rt/image.h"

#include <cctype>
#include <cstdio>
#include <vector>

#include <stb_image_write.h>

#include "rt/error.h"
#include "rt/output_file.h"

namespace rt {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

} // namespace

void check_image_path(const std::string& path) {
  const std::string p = lower(path);
  if (!ends_with(p, ".png") && !ends_with(p, ".pfm"))
    throw UsageError("output '" + path + "': expected a .png or .pfm file name");
  check_output_path(path, "image");
}

void write_png(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0) throw OutputError("cannot write an empty image");
  write_output_file(path, "PNG", [&](std::FILE* file) {
    // stb encodes into memory and hands the bytes over in pieces; fwrite's failures show
    // through ferror() when write_output_file closes the file.
    const auto put = [](void* context, void* data, int size) {
      std::fwrite(data, 1, static_cast<std::size_t>(size), static_cast<std::FILE*>(context));
    };
    if (!stbi_write_png_to_func(put, file, image.width, image.height, 4, image.pixels.data(),
                                image.width * static_cast<int>(sizeof(Rgba8))))
      throw OutputError(path + ": cannot write PNG (the encoder failed: out of memory)");
  });
}

void write_pfm(const std::string& path, int width, int height, std::span<const Vec3f> rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height)
    throw OutputError(path + ": cannot write PFM (the image size does not match its data)");
  write_output_file(path, "PFM", [&](std::FILE* file) {
    // A negative scale marks little-endian data; rows are stored bottom to top.
    std::fprintf(file, "PF\n%d %d\n-1.0\n", width, height);
    std::vector<float> row(static_cast<std::size_t>(width) * 3);
    for (int y = height - 1; y >= 0; --y) {
      const Vec3f* pixel = rgb.data() + static_cast<std::size_t>(y) * width;
      for (int x = 0; x < width; ++x) {
        row[3 * x] = pixel[x].x;
        row[3 * x + 1] = pixel[x].y;
        row[3 * x + 2] = pixel[x].z;
      }
      if (std::fwrite(row.data(), sizeof(float), row.size(), file) != row.size()) return;
    }
  });
}

void write_image(const std::string& path, const Image& image) {
  check_image_path(path);
  if (ends_with(lower(path), ".png")) return write_png(path, image);
  std::vector<Vec3f> rgb(image.pixels.size());
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    const Rgba8 p = image.pixels[i];
    rgb[i] = {p.r / 255.0f, p.g / 255.0f, p.b / 255.0f};
  }
  write_pfm(path, image.width, image.height, rgb);
}

std::size_t count_differing_pixels(std::span<const Rgba8> a, std::span<const Rgba8> b) {
  if (a.size() != b.size()) throw Error("count_differing_pixels: images differ in size");
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differing += a[i] == b[i] ? 0 : 1;
  return differing;
}

} // namespace rt
