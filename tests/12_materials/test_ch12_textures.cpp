// Chapter 12 tests of textures and ray cones: the mip chain against the mean of each texel's
// footprint, worked out by hand; the filters against the texels they read; the limits refused
// from a file's header before anything is decoded; the ray cone's level of detail against the
// pixel's footprint; and, on a GPU, the texture unit and the software filter against the CPU.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "gpu_guard.h"
#include "ray_cone.h"
#include "rt/error.h"
#include "rt/image.h"
#include "run_program.h"
#include "textures.h"

using namespace rt;
using namespace rt::ch12;

namespace {

std::vector<Rgba8> random_texels(int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<Rgba8> texels(count);
  for (Rgba8& t : texels) {
    t = {static_cast<std::uint8_t>(byte(random)), static_cast<std::uint8_t>(byte(random)),
         static_cast<std::uint8_t>(byte(random)), static_cast<std::uint8_t>(byte(random))};
  }
  return texels;
}

// Channel c of a texel, linear, in double: the reference the tests compare with.
double linear_channel(Rgba8 texel, int c, bool srgb) {
  const std::uint8_t bytes[4] = {texel.r, texel.g, texel.b, texel.a};
  return srgb && c < 3 ? srgb_to_linear(bytes[c] / 255.0) : bytes[c] / 255.0;
}

std::uint8_t channel_of(Rgba8 texel, int c) {
  const std::uint8_t bytes[4] = {texel.r, texel.g, texel.b, texel.a};
  return bytes[c];
}

// The texel of level `level` at (x, y).
Rgba8 level_texel(const TextureImage& texture, int level, int x, int y) {
  const TextureLevel& size = texture.levels[level];
  return texture.texels[size.offset + static_cast<long long>(y) * size.width + x];
}

// Every channel of `texel` within one step of the bytes that encode `expected` (linear): the
// chain is computed in float from the previous level's floats, the reference in double.
void check_encodes(Rgba8 texel, const std::array<double, 4>& expected, bool srgb) {
  for (int c = 0; c < 4; ++c) {
    const int want = encode_channel(expected[c], srgb && c < 3);
    INFO("channel " << c << ": texel " << int(channel_of(texel, c)) << ", mean encodes to "
                    << want);
    CHECK(std::abs(int(channel_of(texel, c)) - want) <= 1);
  }
}

std::array<double, 4> mean_of_level(const TextureImage& texture, int level) {
  const TextureLevel& size = texture.levels[level];
  std::array<double, 4> sum{};
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      for (int c = 0; c < 4; ++c) {
        sum[c] += linear_channel(level_texel(texture, level, x, y), c, texture.srgb);
      }
    }
  }
  for (double& s : sum) s /= static_cast<double>(size.width) * size.height;
  return sum;
}

Vec4f decoded(Rgba8 texel, bool srgb) {
  return decode_texel(texel, srgb, texel_decode_table().data());
}

bool same_bits(Vec4f a, Vec4f b) {
  return a.x == b.x && a.y == b.y && a.z == b.z && a.w == b.w;
}

float largest_difference(Vec4f a, Vec4f b) {
  return std::max(
      {std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z), std::abs(a.w - b.w)});
}

template <class Call> std::string input_error_of(Call&& call) {
  try {
    call();
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no error)";
}

bool one_line(const std::string& text) { return text.find('\n') == std::string::npos; }

// A PNG whose header (signature and IHDR chunk, 8-bit RGBA) claims width x height, with no
// pixel data after it: only a reader that trusts the header before decoding can size it.
std::string png_header_only(std::uint32_t width, std::uint32_t height) {
  std::string bytes = "\x89PNG\r\n\x1a\n";
  auto put32 = [&](std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) bytes += static_cast<char>((v >> shift) & 255);
  };
  put32(13);
  bytes += "IHDR";
  put32(width);
  put32(height);
  bytes += std::string("\x08\x06\x00\x00\x00", 5); // 8 bits, RGBA, deflate, no interlace
  put32(0);                                        // CRC, which stb_image does not check
  return bytes;
}

std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = (rt::testing::temp_folder("rt_ch12_textures") / name).string();
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

} // namespace

// ---------------------------------------------------------------------------------------------
// The mip chain

TEST_CASE("Mip levels halve each side down to 1 x 1, max(1, n / 2), for any size",
          "[textures]") {
  const TextureImage one = make_texture("1x1", 1, 1, {{10, 20, 30, 40}}, true);
  REQUIRE(one.level_count() == 1);
  CHECK(one.texels.size() == 1);
  CHECK(one.texels[0] == Rgba8{10, 20, 30, 40});

  const TextureImage odd = make_texture("5x3", 5, 3, random_texels(15, 1), false);
  REQUIRE(odd.level_count() == 3);
  CHECK(odd.levels[1].width == 2);
  CHECK(odd.levels[1].height == 1);
  CHECK(odd.levels[2].width == 1);
  CHECK(odd.levels[2].height == 1);
  CHECK(odd.levels[1].offset == 15);
  CHECK(odd.levels[2].offset == 17);
  CHECK(odd.texels.size() == 18);
  CHECK(texture_bytes(5, 3) == 18 * 4);

  const TextureImage square = make_texture("256", 256, 256, random_texels(256 * 256, 2), true);
  REQUIRE(square.level_count() == 9);
  long long offset = 0;
  for (int level = 0; level < 9; ++level) {
    CHECK(square.levels[level].width == 256 >> level);
    CHECK(square.levels[level].height == 256 >> level);
    CHECK(square.levels[level].offset == offset);
    offset += static_cast<long long>(256 >> level) * (256 >> level);
  }
  CHECK(static_cast<long long>(square.texels.size()) == offset);
  CHECK(texture_bytes(256, 256) == offset * 4);
  CHECK(mip_level_count(1, 1000) == 10); // the long side decides: 1000 -> 500 -> ... -> 1
}

TEST_CASE("A texel of an odd level's next one is the linear mean of its footprint",
          "[textures]") {
  // 5 x 3 becomes 2 x 1: texel 0 covers columns 0, 1 and half of 2, texel 1 the other half of
  // column 2, then 3 and 4; each covers all three rows. The 1 x 1 after it covers everything.
  for (const bool srgb : {false, true}) {
    INFO((srgb ? "sRGB" : "linear"));
    const std::vector<Rgba8> base = random_texels(15, srgb ? 3 : 4);
    const TextureImage texture = make_texture("5x3", 5, 3, base, srgb);
    const double column_weight[2][5] = {{1.0, 1.0, 0.5, 0.0, 0.0}, {0.0, 0.0, 0.5, 1.0, 1.0}};
    for (int i = 0; i < 2; ++i) {
      std::array<double, 4> mean{};
      for (int y = 0; y < 3; ++y) {
        for (int x = 0; x < 5; ++x) {
          for (int c = 0; c < 4; ++c) {
            mean[c] += column_weight[i][x] * linear_channel(base[y * 5 + x], c, srgb) / 7.5;
          }
        }
      }
      check_encodes(level_texel(texture, 1, i, 0), mean, srgb);
    }
    check_encodes(level_texel(texture, 2, 0, 0), mean_of_level(texture, 0), srgb);
  }
}

TEST_CASE("Every level of a 256 x 256 texture is the 2 x 2 linear mean of the one before",
          "[textures]") {
  const TextureImage texture = make_texture("256", 256, 256, random_texels(256 * 256, 5), true);
  for (int level = 1; level < texture.level_count(); ++level) {
    INFO("level " << level);
    const TextureLevel& size = texture.levels[level];
    for (int y = 0; y < size.height; y += std::max(1, size.height / 8)) {
      for (int x = 0; x < size.width; x += std::max(1, size.width / 8)) {
        std::array<double, 4> mean{};
        for (int dy = 0; dy < 2; ++dy) {
          for (int dx = 0; dx < 2; ++dx) {
            const Rgba8 texel = level_texel(texture, level - 1, 2 * x + dx, 2 * y + dy);
            for (int c = 0; c < 4; ++c) mean[c] += 0.25 * linear_channel(texel, c, true);
          }
        }
        // One step more than check_encodes allows: the previous level's bytes are themselves
        // rounded from the floats the chain averaged.
        for (int c = 0; c < 4; ++c) {
          const int want = encode_channel(mean[c], c < 3);
          CHECK(std::abs(int(channel_of(level_texel(texture, level, x, y), c)) - want) <= 2);
        }
      }
    }
  }
  // The 1 x 1 level is the whole image's mean, to one step: rounding did not pile up.
  check_encodes(level_texel(texture, texture.level_count() - 1, 0, 0),
                mean_of_level(texture, 0), true);
}

TEST_CASE("Black and white average to linear grey, sRGB 188, not to the bytes' mean 128",
          "[textures]") {
  const Rgba8 black{0, 0, 0, 255}, white{255, 255, 255, 255};
  const TextureImage checker =
      make_texture("checker", 2, 2, {black, white, white, black}, true);
  CHECK(level_texel(checker, 1, 0, 0) == Rgba8{188, 188, 188, 255});
  const TextureImage data = make_texture("data", 2, 2, {black, white, white, black}, false);
  CHECK(level_texel(data, 1, 0, 0) == Rgba8{128, 128, 128, 255}); // linear data: 127.5 up
}

TEST_CASE("sRGB decode and encode round-trip every byte, and the decode table is the formula",
          "[textures]") {
  const std::span<const float> table = texel_decode_table();
  REQUIRE(table.size() == k_decode_table_size);
  for (int c = 0; c < 256; ++c) {
    INFO("byte " << c);
    CHECK(encode_channel(srgb_to_linear(c / 255.0), true) == c);
    CHECK(encode_channel(table[c], true) == c);
    CHECK(encode_channel(c / 255.0, false) == c);
    CHECK(table[c] == static_cast<float>(srgb_to_linear(c / 255.0)));
    CHECK(table[256 + c] == static_cast<float>(c / 255.0));
    if (c > 0) CHECK(table[c] > table[c - 1]);
  }
  CHECK(table[255] == 1.0f);
  CHECK(table[128] == Approx(0.2158605).epsilon(1e-6)); // IEC 61966-2-1 at 128 / 255
  CHECK(linear_to_srgb(srgb_to_linear(0.5)) == Approx(0.5).epsilon(1e-12));
}

// ---------------------------------------------------------------------------------------------
// The filters, on the CPU

TEST_CASE("Point sampling returns the texel under uv, exactly, v down", "[textures]") {
  const TextureImage texture = make_texture("4x2", 4, 2, random_texels(8, 6), true);
  const HostTextures host(std::span(&texture, 1));
  const TextureTable table = host.table(TextureFilter::point);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) {
      for (const float jitter : {-0.45f, 0.0f, 0.3f}) {
        const Vec2f uv{(x + 0.5f + jitter) / 4.0f, (y + 0.5f - jitter) / 2.0f};
        CHECK(same_bits(sample_texture(table, 0, uv, 0.0f),
                        decoded(texture.texels[y * 4 + x], true)));
      }
    }
  }
  // v = 0.25 is the top row (row 0), as glTF has it.
  CHECK(same_bits(sample_texture(table, 0, {0.1f, 0.25f}, 0.0f),
                  decoded(texture.texels[0], true)));
}

TEST_CASE("Bilinear filtering gives the texel at its centre and the linear mean midway",
          "[textures]") {
  const TextureImage texture = make_texture("8x4", 8, 4, random_texels(32, 7), true);
  const HostTextures host(std::span(&texture, 1));
  const TextureTable table = host.table(TextureFilter::bilinear);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 8; ++x) {
      const Vec2f centre{(x + 0.5f) / 8.0f, (y + 0.5f) / 4.0f};
      CHECK(same_bits(sample_texture(table, 0, centre, 0.0f),
                      decoded(texture.texels[y * 8 + x], true)));
      // Midway to the right-hand neighbour (wrapping at the last column): the mean of the two
      // in linear space, not of their sRGB bytes.
      const Rgba8 left = texture.texels[y * 8 + x], right = texture.texels[y * 8 + (x + 1) % 8];
      const Vec4f mid = sample_texture(table, 0, {(x + 1.0f) / 8.0f, centre.y}, 0.0f);
      const float got[4] = {mid.x, mid.y, mid.z, mid.w};
      for (int c = 0; c < 4; ++c) {
        const double mean =
            0.5 * (linear_channel(left, c, true) + linear_channel(right, c, true));
        CHECK(got[c] == Approx(mean).margin(1e-6));
      }
    }
  }
}

TEST_CASE("Coordinates outside [0, 1] repeat the texture", "[textures]") {
  const TextureImage texture = make_texture("4x4", 4, 4, random_texels(16, 8), false);
  const HostTextures host(std::span(&texture, 1));
  for (const TextureFilter filter : {TextureFilter::point, TextureFilter::bilinear}) {
    INFO(to_string(filter));
    const TextureTable table = host.table(filter);
    const float v = 0.6f;
    CHECK(same_bits(sample_texture(table, 0, {-0.25f, v}, 0.0f),
                    sample_texture(table, 0, {0.75f, v}, 0.0f)));
    CHECK(same_bits(sample_texture(table, 0, {1.25f, v}, 0.0f),
                    sample_texture(table, 0, {0.25f, v}, 0.0f)));
    CHECK(same_bits(sample_texture(table, 0, {0.3f, -0.375f}, 0.0f),
                    sample_texture(table, 0, {0.3f, 0.625f}, 0.0f)));
  }
  // At u = 0 the bilinear filter is halfway between the last column and the first.
  const TextureTable bilinear = host.table(TextureFilter::bilinear);
  const Vec4f edge = sample_texture(bilinear, 0, {0.0f, 0.125f}, 0.0f);
  CHECK(edge.x ==
        Approx(0.5 * (texture.texels[0].r + texture.texels[3].r) / 255.0).margin(1e-6));
}

TEST_CASE("Trilinear filtering at LOD 0 is bilinear, at the last level the mean colour",
          "[textures]") {
  const TextureImage texture = make_texture("16x8", 16, 8, random_texels(128, 9), true);
  const HostTextures host(std::span(&texture, 1));
  const TextureTable bilinear = host.table(TextureFilter::bilinear);
  const TextureTable trilinear = host.table(TextureFilter::trilinear);
  const float last = static_cast<float>(texture.level_count() - 1); // 4: 16 -> 1
  REQUIRE(last == 4.0f);
  const std::array<double, 4> mean = mean_of_level(texture, 0);
  std::mt19937 random(10);
  std::uniform_real_distribution<float> coordinate(-1.0f, 2.0f);
  for (int i = 0; i < 50; ++i) {
    const Vec2f uv{coordinate(random), coordinate(random)};
    CHECK(same_bits(sample_texture(trilinear, 0, uv, 0.0f),
                    sample_texture(bilinear, 0, uv, 0.0f)));
    CHECK(same_bits(sample_texture(trilinear, 0, uv, -3.0f),
                    sample_texture(bilinear, 0, uv, 0.0f)));
    for (const float lod : {last, last + 5.0f}) {
      const Vec4f top = sample_texture(trilinear, 0, uv, lod);
      const float got[4] = {top.x, top.y, top.z, top.w};
      // The 1 x 1 level's bytes hold the mean to within one step of 1/255 (in sRGB, a linear
      // step is at most 1/255 * 12.92 ... near black; a margin of 0.01 holds everywhere).
      for (int c = 0; c < 4; ++c) CHECK(got[c] == Approx(mean[c]).margin(0.01));
    }
    // Halfway between levels 1 and 2: the mean of the two bilinear lookups.
    const Vec4f half = sample_texture(trilinear, 0, uv, 1.5f);
    const Vec4f one = sample_bilinear(trilinear.views[0], trilinear.decode, 1, uv);
    const Vec4f two = sample_bilinear(trilinear.views[0], trilinear.decode, 2, uv);
    CHECK(half.x == Approx(0.5f * (one.x + two.x)).margin(1e-6));
    CHECK(half.w == Approx(0.5f * (one.w + two.w)).margin(1e-6));
  }
  // A NaN level of detail reads level 0; a NaN coordinate reads from 0, never out of bounds.
  CHECK(same_bits(sample_texture(trilinear, 0, {0.3f, 0.7f}, std::nanf("")),
                  sample_texture(bilinear, 0, {0.3f, 0.7f}, 0.0f)));
  const Vec4f nan_uv = sample_texture(trilinear, 0, {std::nanf(""), INFINITY}, 2.0f);
  CHECK(std::isfinite(nan_uv.x + nan_uv.y + nan_uv.z + nan_uv.w));
}

TEST_CASE("No texture reads white, which leaves the factor it scales as it is", "[textures]") {
  const TextureImage texture = make_texture("1x1", 1, 1, {{0, 0, 0, 0}}, true);
  const HostTextures host(std::span(&texture, 1));
  const TextureTable table = host.table(TextureFilter::bilinear);
  CHECK(same_bits(sample_texture(table, -1, {0.5f, 0.5f}, 0.0f), {1.0f, 1.0f, 1.0f, 1.0f}));
  CHECK(same_bits(sample_texture(table, 1, {0.5f, 0.5f}, 0.0f), {1.0f, 1.0f, 1.0f, 1.0f}));
  CHECK(same_bits(sample_texture(table, 0, {0.5f, 0.5f}, 0.0f), {0.0f, 0.0f, 0.0f, 0.0f}));
  CHECK(parse_texture_filter("trilinear") == TextureFilter::trilinear);
  CHECK_THROWS_AS(parse_texture_filter("anisotropic"), UsageError);
}

// ---------------------------------------------------------------------------------------------
// Limits and files

TEST_CASE("Sizes past the limits are refused before anything is allocated", "[textures]") {
  const TextureLimits limits;
  const std::string side =
      input_error_of([&] { check_texture_size("big.png", limits.max_side + 1, 16, limits); });
  CHECK_THAT(side, rt::testing::starts_with("big.png: "));
  CHECK_THAT(side, rt::testing::contains("16385 x 16"));
  CHECK(one_line(side));
  // A size whose bytes would overflow a 64-bit count is refused by its sides first.
  CHECK_THAT(
      input_error_of([&] { check_texture_size("absurd", 2000000000, 2000000000, limits); }),
      rt::testing::contains("larger than"));
  // 16384 x 16384 is allowed a side but not its 1.43 GB with mips; 8192 x 8192 fits.
  CHECK(texture_bytes(16384, 16384) > limits.max_bytes);
  CHECK_THAT(input_error_of([&] { check_texture_size("huge", 16384, 16384, limits); }),
             rt::testing::contains("over the limit"));
  CHECK_NOTHROW(check_texture_size("fits", 8192, 8192, limits));
  // The scene's other textures count: three 8192s fit (1 073 741 820 bytes, 4 under 1 GiB),
  // a fourth does not.
  const long long one = texture_bytes(8192, 8192);
  CHECK_NOTHROW(check_texture_size("third", 8192, 8192, limits, 2 * one));
  CHECK_THROWS_AS(check_texture_size("fourth", 8192, 8192, limits, 3 * one), InputError);
  CHECK_THROWS_AS(check_texture_size("empty", 0, 4, limits), InputError);
  // make_texture checks the size before it reads a texel: the level is not even there.
  CHECK_THAT(input_error_of([&] { make_texture("made", 20000, 20000, {}, true); }),
             rt::testing::starts_with("made: "));
  CHECK_THAT(input_error_of([&] { make_texture("short", 4, 4, random_texels(15, 1), true); }),
             rt::testing::contains("15 texels"));
  const std::vector<TextureImage> two{make_texture("a", 8, 8, random_texels(64, 1), true),
                                      make_texture("b", 8, 8, random_texels(64, 2), true)};
  CHECK_NOTHROW(check_texture_total(two, limits, "scene.gltf"));
  CHECK_THAT(input_error_of([&] {
               check_texture_total(two, {16384, 400}, "scene.gltf");
             }),
             rt::testing::starts_with("scene.gltf: "));
}

TEST_CASE("A PNG header claiming a huge size is refused from the header", "[textures]") {
  // No pixel data follows the header: a reader that decoded first would fail on the data, or
  // try to allocate 800 MB; the refusal names the size, so it came from the header.
  const std::string path = write_file("huge.png", png_header_only(20000, 10000));
  const std::string error = input_error_of([&] { load_texture(path, true); });
  CHECK_THAT(error, rt::testing::starts_with(path + ": "));
  CHECK_THAT(error, rt::testing::contains("20000 x 10000"));
  CHECK_THAT(error, rt::testing::contains("larger than"));
  CHECK(one_line(error));
  // Within the sides but over the bytes: 12000 x 12000 with mips is 768 MB, over 100 MB.
  const std::string wide = write_file("wide.png", png_header_only(12000, 12000));
  const std::string over = input_error_of([&] {
    load_texture(wide, true, {16384, 100 << 20});
  });
  CHECK_THAT(over, rt::testing::starts_with(wide + ": "));
  CHECK_THAT(over, rt::testing::contains("over the limit"));
}

TEST_CASE("Missing and corrupt texture files are one-line input errors naming the file",
          "[textures]") {
  const std::string missing =
      (rt::testing::temp_folder("rt_ch12_textures") / "no_such_texture.png").string();
  const std::string error = input_error_of([&] { load_texture(missing, true); });
  CHECK_THAT(error, rt::testing::starts_with(missing + ": "));
  CHECK_THAT(error, rt::testing::contains("no such file"));
  CHECK(one_line(error));
  const std::string folder = rt::testing::temp_folder("rt_ch12_textures").string();
  CHECK_THAT(input_error_of([&] { load_texture(folder, true); }),
             rt::testing::contains("not a file"));

  for (const std::string& bytes :
       {std::string("\x89PNG\r\n\x1a\n garbage after a PNG signature"),
        std::string("not an image at all"), std::string()}) {
    const std::string path = write_file("corrupt.png", bytes);
    const std::string corrupt = input_error_of([&] { load_texture(path, false); });
    CHECK_THAT(corrupt, rt::testing::starts_with(path + ": "));
    CHECK(one_line(corrupt));
  }
  // A header that is whole, then pixel data that is not: refused by the decoder, still one
  // line naming the file.
  const std::string truncated = write_file("truncated.png", png_header_only(4, 4));
  const std::string cut = input_error_of([&] { load_texture(truncated, true); });
  CHECK_THAT(cut, rt::testing::starts_with(truncated + ": "));
  CHECK(one_line(cut));
}

TEST_CASE("A PNG written by stb_image_write loads back the same texels", "[textures]") {
  Image image(7, 5); // odd sides, so the rows are not padded to anything
  const std::vector<Rgba8> texels = random_texels(35, 11);
  image.pixels = texels;
  const std::string path =
      (rt::testing::temp_folder("rt_ch12_textures") / "round.png").string();
  write_png(path, image);
  const TextureImage loaded = load_texture(path, true);
  CHECK(loaded.name == path);
  CHECK(loaded.width == 7);
  CHECK(loaded.height == 5);
  CHECK(loaded.srgb);
  REQUIRE(loaded.level_count() == 3);
  CHECK(std::equal(texels.begin(), texels.end(), loaded.texels.begin()));
  // Over a byte limit smaller than the file's texels: refused, naming the file.
  CHECK_THAT(input_error_of([&] {
               load_texture(path, true, {16384, 100});
             }),
             rt::testing::starts_with(path + ": "));
}

// ---------------------------------------------------------------------------------------------
// Ray cones

TEST_CASE("A pinhole camera's cone spreads by the angle of one pixel", "[textures]") {
  const double half_fov = 30.0 * std::numbers::pi / 180.0;
  for (const int height : {1, 480, 2160}) {
    const double expected = std::atan(2.0 * std::tan(half_fov) / height);
    CHECK(pinhole_spread_angle(static_cast<float>(std::tan(half_fov)), height) ==
          Approx(expected).epsilon(1e-6));
  }
  const RayCone cone = camera_ray_cone(1.0f, 1000); // 90 degrees
  CHECK(cone.width == 0.0f);
  CHECK(cone.spread == Approx(std::atan(0.002)).epsilon(1e-6));
  const RayCone far = propagate(propagate(cone, 3.0f), 2.0f);
  CHECK(far.width == Approx(5.0 * std::atan(0.002)).epsilon(1e-6));
  CHECK(far.spread == cone.spread);
}

namespace {

// The LOD at the centre of a square quad that fills a square image of `pixels` pixels, seen
// head-on from `distance` by a camera of vertical fov 2 * atan(tan_half) (the quad is sized to
// fill the view at `fill_distance`), textured with a `texels`-square texture.
float quad_centre_lod(int pixels, int texels, float distance, float fill_distance,
                      bool clamp = true) {
  const float tan_half = 0.5f;
  const float half = fill_distance * tan_half;
  const Vec3f p0{-half, -half, -distance}, p1{half, -half, -distance},
      p2{half, half, -distance};
  const float constant = triangle_lod_constant(p0, p1, p2, {0.0f, 1.0f}, {1.0f, 1.0f},
                                               {1.0f, 0.0f}, texels, texels);
  const RayCone cone = propagate(camera_ray_cone(tan_half, pixels), distance);
  return clamp ? cone_texture_lod(constant, cone, 1.0f) : constant + std::log2(cone.width);
}

} // namespace

TEST_CASE("A quad filling the screen with one texel per pixel is read at LOD 0", "[textures]") {
  for (const int pixels : {256, 1024}) {
    INFO(pixels << " pixels");
    // One texel per pixel: log2(atan(x) / x) for x = 2 tan(fov / 2) / height, some -1e-6.
    CHECK(std::abs(quad_centre_lod(pixels, pixels, 10.0f, 10.0f, false)) < 1e-3f);
    CHECK(quad_centre_lod(pixels, pixels, 10.0f, 10.0f) < 1e-3f);
    // Four texels a pixel each way: two levels up.
    CHECK(quad_centre_lod(pixels, 4 * pixels, 10.0f, 10.0f) == Approx(2.0f).margin(1e-3));
  }
}

TEST_CASE("Twice as far, the level of detail is one more", "[textures]") {
  for (const float distance : {0.5f, 10.0f, 4000.0f}) {
    INFO("distance " << distance);
    const float near_lod = quad_centre_lod(512, 2048, distance, distance);
    const float far_lod = quad_centre_lod(512, 2048, 2.0f * distance, distance);
    CHECK(near_lod == Approx(2.0f).margin(1e-3));
    CHECK(far_lod - near_lod == Approx(1.0f).margin(1e-4));
  }
  // Seen at 60 degrees the footprint is twice as long: one more level as well.
  const RayCone cone{0.01f, 0.0f};
  CHECK(cone_texture_lod(10.0f, cone, 0.5f) - cone_texture_lod(10.0f, cone, 1.0f) ==
        Approx(1.0f).margin(1e-5));
}

TEST_CASE("Grazing hits, degenerate uv and triangles give a finite, clamped LOD",
          "[textures]") {
  const Vec3f p0{0.0f, 0.0f, 0.0f}, p1{1.0f, 0.0f, 0.0f}, p2{0.0f, 1.0f, 0.0f};
  const Vec2f a{0.0f, 0.0f}, b{1.0f, 0.0f}, c{0.0f, 1.0f};
  const RayCone cone{0.01f, 0.001f};
  for (const float cosine : {0.0f, -0.0f, 1e-30f, -1e-8f, std::nanf(""), INFINITY}) {
    INFO("cos " << cosine);
    const float lod =
        cone_texture_lod(triangle_lod_constant(p0, p1, p2, a, b, c, 1024, 1024), cone, cosine);
    CHECK(std::isfinite(lod));
    CHECK(lod >= 0.0f);
    CHECK(lod <= k_max_cone_lod);
  }
  // uv all on a line, or all the same: the texture is constant across the triangle.
  CHECK(triangle_lod_constant(p0, p1, p2, a, b, {2.0f, 0.0f}, 1024, 1024) == 0.0f);
  CHECK(triangle_lod_constant(p0, p1, p2, a, a, a, 1024, 1024) == 0.0f);
  // A triangle of no area, or one with a NaN corner, or uv of 1e30.
  CHECK(triangle_lod_constant(p0, p1, {2.0f, 0.0f, 0.0f}, a, b, c, 64, 64) == 0.0f);
  CHECK(triangle_lod_constant(p0, p1, {std::nanf(""), 0.0f, 0.0f}, a, b, c, 64, 64) == 0.0f);
  CHECK(std::isfinite(
      triangle_lod_constant(p0, p1, p2, a, {1e30f, 0.0f}, {0.0f, 1e30f}, 64, 64)));
  // A cone of width 0 (at the eye) or NaN reads level 0.
  CHECK(cone_texture_lod(3.0f, {0.0f, 0.1f}, 1.0f) == 0.0f);
  CHECK(cone_texture_lod(3.0f, {std::nanf(""), 0.1f}, 1.0f) == 0.0f);
  CHECK(cone_texture_lod(3.0f, {1e30f, 0.1f}, 1.0f) == k_max_cone_lod);
}

TEST_CASE("A bounce keeps the cone's spread on mirrors and widens it on rough and diffuse",
          "[textures]") {
  const RayCone cone{0.02f, 0.001f};
  const RayCone mirror = bounce_cone(cone, ConeBounce::specular, 0.0f);
  CHECK(mirror.width == cone.width);
  CHECK(mirror.spread == cone.spread);
  const RayCone rough = bounce_cone(cone, ConeBounce::rough, 0.09f);
  CHECK(rough.width == cone.width);
  CHECK(rough.spread == Approx(0.091f));
  CHECK(bounce_cone(cone, ConeBounce::rough, 50.0f).spread == k_diffuse_cone_spread);
  const RayCone diffuse = bounce_cone(cone, ConeBounce::diffuse, 0.0f);
  CHECK(diffuse.width == cone.width);
  CHECK(diffuse.spread == k_diffuse_cone_spread);
  // After a diffuse bounce, a hit one unit on reads several levels coarser than a mirror's.
  const float constant = 10.0f;
  CHECK(cone_texture_lod(constant, propagate(diffuse, 1.0f), 1.0f) >
        cone_texture_lod(constant, propagate(mirror, 1.0f), 1.0f) + 5.0f);
}

// ---------------------------------------------------------------------------------------------
// On the GPU: the same texels and filters as the CPU.

namespace {

// Two sRGB colour textures and one of linear data, of sizes that are and are not powers of two.
std::vector<TextureImage> gpu_textures() {
  std::vector<TextureImage> textures;
  textures.push_back(make_texture("colour 8x4", 8, 4, random_texels(32, 21), true));
  textures.push_back(make_texture("colour 37x19", 37, 19, random_texels(37 * 19, 22), true));
  textures.push_back(make_texture("data 5x3", 5, 3, random_texels(15, 23), false));
  return textures;
}

// Queries at texel centres moved at most 0.3 texel: never near the edge between two texels,
// where the texture unit's fixed-point coordinates may round to the neighbour.
std::vector<TextureQuery> point_queries(const std::vector<TextureImage>& textures) {
  std::mt19937 random(24);
  std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
  std::uniform_int_distribution<int> turn(-2, 2);
  std::vector<TextureQuery> queries;
  for (int index = 0; index < static_cast<int>(textures.size()); ++index) {
    const TextureImage& texture = textures[index];
    for (int y = 0; y < texture.height; ++y) {
      for (int x = 0; x < texture.width; ++x) {
        const float u = (x + 0.5f + jitter(random)) / texture.width + turn(random);
        const float v = (y + 0.5f + jitter(random)) / texture.height + turn(random);
        queries.push_back({index, {u, v}, 0.0f});
      }
    }
  }
  queries.push_back({-1, {0.5f, 0.5f}, 0.0f}); // no texture: white on both
  return queries;
}

std::vector<TextureQuery> filter_queries(const std::vector<TextureImage>& textures) {
  std::mt19937 random(25);
  std::uniform_real_distribution<float> coordinate(-2.0f, 3.0f);
  std::uniform_real_distribution<float> lod(-1.0f, 7.0f);
  std::vector<TextureQuery> queries;
  for (int i = 0; i < 3000; ++i) {
    queries.push_back({i % static_cast<int>(textures.size()),
                       {coordinate(random), coordinate(random)},
                       lod(random)});
  }
  return queries;
}

std::vector<Vec4f> sample_on_cpu(const TextureTable& table,
                                 const std::vector<TextureQuery>& queries) {
  std::vector<Vec4f> results;
  for (const TextureQuery& q : queries)
    results.push_back(sample_texture(table, q.index, q.uv, q.lod));
  return results;
}

} // namespace

TEST_CASE("GPU point sampling gives the CPU's texels exactly, through texture objects and "
          "plain loads",
          "[textures][gpu]") {
  RT_REQUIRE_GPU();
  const std::vector<TextureImage> textures = gpu_textures();
  const HostTextures host(textures);
  const DeviceTextures device(textures);
  const std::vector<TextureQuery> queries = point_queries(textures);
  const std::vector<Vec4f> cpu = sample_on_cpu(host.table(TextureFilter::point), queries);
  for (const bool objects_on : {true, false}) {
    INFO((objects_on ? "texture objects" : "plain loads"));
    const std::vector<Vec4f> gpu =
        sample_textures_on_gpu(device.table(TextureFilter::point, objects_on), queries);
    REQUIRE(gpu.size() == cpu.size());
    int differing = 0;
    for (std::size_t i = 0; i < cpu.size(); ++i) differing += !same_bits(cpu[i], gpu[i]);
    CHECK(differing == 0);
  }
}

TEST_CASE("The GPU's software filter gives the CPU's results bit for bit", "[textures][gpu]") {
  RT_REQUIRE_GPU();
  const std::vector<TextureImage> textures = gpu_textures();
  const HostTextures host(textures);
  const DeviceTextures device(textures);
  const std::vector<TextureQuery> queries = filter_queries(textures);
  for (const TextureFilter filter :
       {TextureFilter::point, TextureFilter::bilinear, TextureFilter::trilinear}) {
    INFO(to_string(filter));
    const std::vector<Vec4f> cpu = sample_on_cpu(host.table(filter), queries);
    const std::vector<Vec4f> gpu = sample_textures_on_gpu(device.table(filter, false), queries);
    REQUIRE(gpu.size() == cpu.size());
    int differing = 0;
    for (std::size_t i = 0; i < cpu.size(); ++i) differing += !same_bits(cpu[i], gpu[i]);
    CHECK(differing == 0);
  }
}

TEST_CASE("The texture unit's bilinear and trilinear filters are within the stated tolerance "
          "of the CPU's",
          "[textures][gpu]") {
  RT_REQUIRE_GPU();
  const std::vector<TextureImage> textures = gpu_textures();
  const HostTextures host(textures);
  const DeviceTextures device(textures);
  const std::vector<TextureQuery> queries = filter_queries(textures);
  for (const TextureFilter filter : {TextureFilter::bilinear, TextureFilter::trilinear}) {
    INFO(to_string(filter));
    const std::vector<Vec4f> cpu = sample_on_cpu(host.table(filter), queries);
    const std::vector<Vec4f> gpu = sample_textures_on_gpu(device.table(filter, true), queries);
    REQUIRE(gpu.size() == cpu.size());
    float worst = 0.0f, sum = 0.0f;
    for (std::size_t i = 0; i < cpu.size(); ++i) {
      const float difference = largest_difference(cpu[i], gpu[i]);
      worst = std::max(worst, difference);
      sum += difference;
    }
    INFO("largest difference " << worst << ", mean " << sum / cpu.size());
    CHECK(worst <= k_hardware_filter_tolerance);
    // Not vacuous: the texture unit does filter (its results are not the point samples').
    const std::vector<Vec4f> point = sample_on_cpu(host.table(TextureFilter::point), queries);
    float from_point = 0.0f;
    for (std::size_t i = 0; i < gpu.size(); ++i) {
      from_point = std::max(from_point, largest_difference(point[i], gpu[i]));
    }
    CHECK(from_point > 10.0f * k_hardware_filter_tolerance);
  }
}

TEST_CASE("DeviceTextures frees every array and texture object, moved or not",
          "[textures][gpu]") {
  RT_REQUIRE_GPU();
  const long long arrays = DeviceTextures::live_arrays();
  const long long objects = DeviceTextures::live_objects();
  {
    const std::vector<TextureImage> textures = gpu_textures();
    DeviceTextures first(textures);
    CHECK(DeviceTextures::live_arrays() == arrays + 3);
    CHECK(DeviceTextures::live_objects() == objects + 9);
    DeviceTextures second(std::move(first));
    CHECK(first.count() == 0);
    CHECK(second.count() == 3);
    DeviceTextures third;
    third = std::move(second);
    CHECK(DeviceTextures::live_arrays() == arrays + 3);
  }
  CHECK(DeviceTextures::live_arrays() == arrays);
  CHECK(DeviceTextures::live_objects() == objects);
}

TEST_CASE("No textures make an empty table and no CUDA call", "[textures]") {
  const DeviceTextures none(std::span<const TextureImage>{});
  const TextureTable table = none.table(TextureFilter::trilinear, true);
  CHECK(table.count == 0);
  CHECK(table.views == nullptr);
  CHECK(DeviceTextures::live_arrays() == 0);
}
