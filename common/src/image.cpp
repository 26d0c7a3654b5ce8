// Image output (chapter 01): see rt/image.h.
#include "rt/image.h"

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include <stb_image_write.h>
#include <tinyexr.h>

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

bool is_linear_image_path(const std::string& path) {
  const std::string p = lower(path);
  return ends_with(p, ".pfm") || ends_with(p, ".exr");
}

void check_image_path(const std::string& path) {
  if (!ends_with(lower(path), ".png") && !is_linear_image_path(path))
    throw UsageError("output '" + path + "': expected a .png, .pfm or .exr file name");
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

void write_exr(const std::string& path, int width, int height, std::span<const Vec3f> rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height)
    throw OutputError(path + ": cannot write EXR (the image size does not match its data)");
  // OpenEXR stores one plane per channel, and readers expect the channels sorted by name:
  // B, G, R. 32-bit floats in and out, so the file holds the values exactly.
  const std::size_t n = rgb.size();
  std::vector<float> planes[3] = {std::vector<float>(n), std::vector<float>(n),
                                  std::vector<float>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    planes[0][i] = rgb[i].z;
    planes[1][i] = rgb[i].y;
    planes[2][i] = rgb[i].x;
  }
  float* plane_pointers[3] = {planes[0].data(), planes[1].data(), planes[2].data()};
  EXRImage exr_image;
  InitEXRImage(&exr_image);
  exr_image.num_channels = 3;
  exr_image.images = reinterpret_cast<unsigned char**>(plane_pointers);
  exr_image.width = width;
  exr_image.height = height;
  EXRChannelInfo channels[3] = {};
  int pixel_types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT,
                        TINYEXR_PIXELTYPE_FLOAT};
  const char* names[3] = {"B", "G", "R"};
  for (int c = 0; c < 3; ++c) std::snprintf(channels[c].name, 255, "%s", names[c]);
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = 3;
  header.channels = channels;
  header.pixel_types = pixel_types;
  header.requested_pixel_types = pixel_types;
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
  unsigned char* memory = nullptr;
  const char* error = nullptr;
  const std::size_t size = SaveEXRImageToMemory(&exr_image, &header, &memory, &error);
  const std::unique_ptr<unsigned char, void (*)(void*)> bytes(memory, std::free);
  if (size == 0) {
    const std::string reason = error != nullptr ? error : "the encoder failed";
    FreeEXRErrorMessage(error);
    throw OutputError(path + ": cannot write EXR (" + reason + ")");
  }
  write_output_file(path, "EXR", [&](std::FILE* file) {
    std::fwrite(bytes.get(), 1, size, file); // a short write shows through ferror()
  });
}

void write_image(const std::string& path, const Image& image) {
  check_image_path(path);
  if (!is_linear_image_path(path)) return write_png(path, image);
  LinearImage values{image.width, image.height, std::vector<Vec3f>(image.pixels.size())};
  for (std::size_t i = 0; i < values.rgb.size(); ++i) {
    const Rgba8 p = image.pixels[i];
    values.rgb[i] = {p.r / 255.0f, p.g / 255.0f, p.b / 255.0f};
  }
  write_linear_image(path, values);
}

void write_linear_image(const std::string& path, const LinearImage& image) {
  check_image_path(path);
  if (!is_linear_image_path(path))
    throw UsageError("output '" + path + "': linear values go to a .pfm or .exr file");
  if (ends_with(lower(path), ".exr"))
    return write_exr(path, image.width, image.height, image.rgb);
  write_pfm(path, image.width, image.height, image.rgb);
}

std::size_t count_differing_pixels(std::span<const Rgba8> a, std::span<const Rgba8> b) {
  if (a.size() != b.size()) throw Error("count_differing_pixels: images differ in size");
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differing += a[i] == b[i] ? 0 : 1;
  return differing;
}

} // namespace rt
