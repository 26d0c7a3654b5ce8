// Image output: PNG and PFM round trips, and unwritable paths as clear errors.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "rt_catch.h"
#include <stb_image.h>
#include <tinyexr.h>

#include "rt/error.h"
#include "rt/image.h"

using namespace rt;
namespace fs = std::filesystem;

namespace {

fs::path temp_path(const std::string& name) {
  return fs::temp_directory_path() / ("rt_test_" + std::to_string(::getpid()) + "_" + name);
}

Image test_image() {
  Image image(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x)
      image.at(x, y) = {std::uint8_t(x * 50), std::uint8_t(y * 100), std::uint8_t(x + y), 255};
  return image;
}

} // namespace

TEST_CASE("PNG round trip keeps every pixel", "[common]") {
  const Image image = test_image();
  const fs::path path = temp_path("a.png");
  write_image(path.string(), image);
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &w, &h, &channels, 4);
  REQUIRE(data != nullptr);
  CHECK(w == 5);
  CHECK(h == 3);
  CHECK(std::memcmp(data, image.pixels.data(), image.pixels.size() * 4) == 0);
  stbi_image_free(data);
  fs::remove(path);
}

TEST_CASE("PFM holds the header and float rows bottom to top", "[common]") {
  const Image image = test_image();
  const fs::path path = temp_path("a.pfm");
  write_image(path.string(), image);
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  int w = 0, h = 0;
  float scale = 0;
  in >> magic >> w >> h >> scale;
  in.get(); // the single newline before the data
  CHECK(magic == "PF");
  CHECK(w == 5);
  CHECK(h == 3);
  CHECK(scale == -1.0f);
  std::vector<float> data(5 * 3 * 3);
  in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * sizeof(float)));
  REQUIRE(in);
  // The first stored row is the image's bottom row (y = 2).
  CHECK(data[0] == 0.0f);
  CHECK(data[1] == Approx(200 / 255.0f));
  CHECK(data[3 * 4 + 0] == Approx(200 / 255.0f)); // x = 4: red 200
  fs::remove(path);
}

TEST_CASE("EXR holds linear floats exactly, HDR values and all", "[common]") {
  // Values a PNG could not hold: above 1, tiny, negative zero's neighbour, a large radiance.
  LinearImage linear{3, 2, {}};
  for (int i = 0; i < 6; ++i)
    linear.rgb.push_back({0.25f * float(i), 1e-6f * float(i + 1), 4.0e29f / float(i + 1)});
  const fs::path exr = temp_path("linear.exr"), pfm = temp_path("linear.pfm");
  write_linear_image(exr.string(), linear);
  write_linear_image(pfm.string(), linear);
  float* rgba = nullptr;
  int w = 0, h = 0;
  const char* error = nullptr;
  REQUIRE(LoadEXR(&rgba, &w, &h, exr.string().c_str(), &error) == TINYEXR_SUCCESS);
  CHECK(w == 3);
  CHECK(h == 2);
  for (int i = 0; i < 6; ++i) { // LoadEXR gives RGBA rows top to bottom
    CHECK(rgba[4 * i + 0] == linear.rgb[i].x);
    CHECK(rgba[4 * i + 1] == linear.rgb[i].y);
    CHECK(rgba[4 * i + 2] == linear.rgb[i].z);
  }
  std::free(rgba);
  std::ifstream in(pfm, std::ios::binary);
  std::string magic;
  float scale = 0;
  in >> magic >> w >> h >> scale;
  in.get();
  std::vector<float> data(18);
  in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * sizeof(float)));
  REQUIRE(in);
  CHECK(data[0] == linear.rgb[3].x); // the bottom row first
  CHECK(data[2] == linear.rgb[3].z);
  fs::remove(exr);
  fs::remove(pfm);
}

TEST_CASE("unwritable or unknown output paths are clear errors", "[common]") {
  const Image image = test_image();
  CHECK_THROWS_AS(write_image("/nonexistent-dir/x.png", image), OutputError);
  CHECK_THROWS_WITH(write_image("/nonexistent-dir/x.png", image),
                    rt::testing::contains("/nonexistent-dir/x.png"));
  CHECK_THROWS_AS(write_image("/nonexistent-dir/x.pfm", image), OutputError);
  CHECK_THROWS_AS(write_image("picture.jpg", image), UsageError);
  CHECK_NOTHROW(check_image_path("A.PNG"));
  CHECK_NOTHROW(check_image_path("b.Exr"));
  CHECK_THROWS_AS(write_linear_image("linear.png", LinearImage{1, 1, {Vec3f{1, 2, 3}}}),
                  UsageError);
  CHECK_THROWS_AS(write_png("/tmp/empty.png", Image{}), OutputError);
}

TEST_CASE("count_differing_pixels", "[common]") {
  Image a = test_image(), b = test_image();
  CHECK(count_differing_pixels(a.pixels, b.pixels) == 0);
  b.at(1, 1).g ^= 1;
  b.at(4, 2).a = 0;
  CHECK(count_differing_pixels(a.pixels, b.pixels) == 2);
  CHECK_THROWS_AS(count_differing_pixels(a.pixels, Image(1, 1).pixels), Error);
}
