// Reading images back in tests: see image_files.h.
#include "image_files.h"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <stb_image.h>
#include <tinyexr.h>

#include "rt_catch.h"

namespace rt::testing {

Image read_png(const std::filesystem::path& path) {
  int width = 0, height = 0, channels = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &width, &height, &channels, 4);
  INFO(path.string());
  REQUIRE(data != nullptr);
  Image image(width, height);
  std::memcpy(image.pixels.data(), data, image.pixels.size() * sizeof(Rgba8));
  stbi_image_free(data);
  return image;
}

LinearImage read_pfm(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  LinearImage image;
  double scale = 0.0;
  in >> magic >> image.width >> image.height >> scale;
  in.get(); // the single white-space character before the data
  INFO(path.string());
  REQUIRE(magic == "PF");
  REQUIRE(scale < 0.0); // little-endian
  std::vector<float> data(std::size_t(image.width) * image.height * 3);
  in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * sizeof(float)));
  REQUIRE(in);
  for (int y = image.height - 1; y >= 0; --y)
    for (int x = 0; x < image.width; ++x) {
      const float* p = &data[3 * (std::size_t(y) * image.width + x)];
      image.rgb.push_back({p[0], p[1], p[2]});
    }
  return image;
}

LinearImage read_exr(const std::filesystem::path& path) {
  float* rgba = nullptr;
  LinearImage image;
  const char* error = nullptr;
  const int code = LoadEXR(&rgba, &image.width, &image.height, path.string().c_str(), &error);
  INFO(path.string() << ": " << (error != nullptr ? error : "read"));
  FreeEXRErrorMessage(error);
  REQUIRE(code == TINYEXR_SUCCESS);
  for (std::size_t i = 0; i < std::size_t(image.width) * image.height; ++i)
    image.rgb.push_back({rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]});
  std::free(rgba);
  return image;
}

} // namespace rt::testing
