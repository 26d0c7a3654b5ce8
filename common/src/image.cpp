// Image output (chapter 01): see rt/image.h.
#include "rt/image.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

#include <stb_image_write.h>

#include "rt/error.h"

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

[[noreturn]] void fail_write(const std::string& what, const std::string& path, int error) {
  throw OutputError("cannot write " + what + " '" + path + "'" +
                    (error != 0 ? std::string(": ") + std::strerror(error) : std::string()));
}

} // namespace

void check_image_path(const std::string& path) {
  const std::string p = lower(path);
  if (!ends_with(p, ".png") && !ends_with(p, ".pfm"))
    throw UsageError("output '" + path + "': expected a .png or .pfm file name");
}

void write_png(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0) throw OutputError("cannot write an empty image");
  errno = 0;
  const int ok = stbi_write_png(path.c_str(), image.width, image.height, 4, image.pixels.data(),
                                image.width * static_cast<int>(sizeof(Rgba8)));
  if (!ok) fail_write("PNG", path, errno);
}

void write_pfm(const std::string& path, int width, int height, std::span<const Vec3f> rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height)
    throw OutputError("cannot write PFM '" + path + "': image size does not match its data");
  errno = 0;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "wb"),
                                                       &std::fclose);
  if (!file) fail_write("PFM", path, errno);
  // A negative scale marks little-endian data; rows are stored bottom to top.
  std::fprintf(file.get(), "PF\n%d %d\n-1.0\n", width, height);
  for (int y = height - 1; y >= 0; --y) {
    const Vec3f* row = rgb.data() + static_cast<std::size_t>(y) * width;
    for (int x = 0; x < width; ++x) {
      const float values[3] = {row[x].x, row[x].y, row[x].z};
      std::fwrite(values, sizeof(float), 3, file.get());
    }
  }
  if (std::ferror(file.get()) || std::fclose(file.release()) != 0)
    fail_write("PFM", path, errno);
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
