// Chapter 12: textures on the host: reading an image, checking its size first, and making its
// mip chain. See textures.h.
#include "textures.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <filesystem>
#include <utility>

#include <stb_image.h>

#include "rt/error.h"

namespace rt::ch12 {

int mip_level_count(int width, int height) {
  int side = std::max(width, height), levels = 1;
  while (side > 1) {
    side /= 2;
    ++levels;
  }
  return levels;
}

long long texture_bytes(int width, int height) {
  long long bytes = 0;
  for (int level = 0, levels = mip_level_count(width, height); level < levels; ++level) {
    bytes += 4LL * std::max(1, width >> level) * std::max(1, height >> level);
  }
  return bytes;
}

long long texture_bytes(std::span<const TextureImage> textures) {
  long long bytes = 0;
  for (const TextureImage& texture : textures)
    bytes += texture_bytes(texture.width, texture.height);
  return bytes;
}

void check_texture_size(const std::string& name, int width, int height,
                        const TextureLimits& limits, long long bytes_before) {
  const std::string size = std::to_string(width) + " x " + std::to_string(height);
  if (width <= 0 || height <= 0)
    throw InputError(name + ": a " + size + " texture has no texels");
  // The sides first: the bytes of an absurd size would overflow before they were compared.
  const int longest = 1 << (k_max_levels - 1);
  if (width > limits.max_side || height > limits.max_side || width > longest ||
      height > longest) {
    throw InputError(name + ": a " + size + " texture is larger than the limit of " +
                     std::to_string(std::min(limits.max_side, longest)) + " texels a side");
  }
  const long long bytes = texture_bytes(width, height);
  if (bytes_before + bytes > limits.max_bytes) {
    throw InputError(name + ": a " + size + " texture with its mip levels takes " +
                     std::to_string(bytes) + " bytes, which with the scene's other textures (" +
                     std::to_string(bytes_before) + ") is over the limit of " +
                     std::to_string(limits.max_bytes));
  }
  // TextureView's offsets are ints: one texture's texels must count below 2^31.
  if (bytes / 4 > INT_MAX) {
    throw InputError(name + ": a " + size + " texture has more than 2^31 texels in its levels");
  }
}

void check_texture_total(std::span<const TextureImage> textures, const TextureLimits& limits,
                         const std::string& where) {
  const long long bytes = texture_bytes(textures);
  if (bytes > limits.max_bytes) {
    throw InputError(where + ": its " + std::to_string(textures.size()) + " textures take " +
                     std::to_string(bytes) +
                     " bytes with their mip levels, over the limit of " +
                     std::to_string(limits.max_bytes));
  }
}

double srgb_to_linear(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

double linear_to_srgb(double linear) {
  return linear <= 0.0031308 ? linear * 12.92 : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

std::uint8_t encode_channel(double linear, bool srgb) {
  if (!(linear >= 0.0)) linear = 0.0; // NaN too: std::clamp would keep it
  linear = std::min(linear, 1.0);
  const double encoded = srgb ? linear_to_srgb(linear) : linear;
  return static_cast<std::uint8_t>(std::lround(encoded * 255.0));
}

std::span<const float> texel_decode_table() {
  static const std::array<float, k_decode_table_size> table = [] {
    std::array<float, k_decode_table_size> made{};
    for (int c = 0; c < 256; ++c) {
      made[c] = static_cast<float>(srgb_to_linear(c / 255.0));
      made[256 + c] = static_cast<float>(c / 255.0);
    }
    return made;
  }();
  return table;
}

namespace {

// [listing:mip_footprint]
// A level of n texels on one axis becomes max(1, floor(n / 2)): texel i of the smaller level
// covers [i * s, (i + 1) * s) of the larger one, s = n / that size. Each texel of the larger
// level is weighted by how much of it lies inside: 1/2 and 1/2 for an even n (the 2x2 box),
// 0.4, 0.4, 0.2 and then 0.2, 0.4, 0.4 for n = 5, a third each for n = 3 (down to 1), so no
// texel of an odd row is dropped and every level keeps the image's mean.
struct Tap {
  int index;
  double weight;
};

std::vector<std::vector<Tap>> footprint_taps(int size) {
  const int smaller = std::max(1, size / 2);
  const double scale = static_cast<double>(size) / smaller;
  std::vector<std::vector<Tap>> taps(smaller);
  for (int i = 0; i < smaller; ++i) {
    const double begin = i * scale, end = (i + 1) * scale;
    for (int j = static_cast<int>(std::floor(begin)); j < size && j < end; ++j) {
      const double overlap = std::min(end, j + 1.0) - std::max(begin, static_cast<double>(j));
      if (overlap > 0.0) taps[i].push_back({j, overlap / scale});
    }
  }
  return taps;
}
// [/listing:mip_footprint]

using Linear = std::array<float, 4>; // one texel, linear RGBA

// The next level of a width x height level given in linear floats: box-filtered in linear
// space (averaging sRGB bytes would darken it), then encoded to bytes.
std::vector<Linear> next_level(const std::vector<Linear>& level, int width, int height) {
  const std::vector<std::vector<Tap>> taps_x = footprint_taps(width);
  const std::vector<std::vector<Tap>> taps_y = footprint_taps(height);
  std::vector<Linear> next(taps_x.size() * taps_y.size());
  for (std::size_t y = 0; y < taps_y.size(); ++y) {
    for (std::size_t x = 0; x < taps_x.size(); ++x) {
      std::array<double, 4> sum{};
      for (const Tap& row : taps_y[y]) {
        for (const Tap& column : taps_x[x]) {
          const Linear& texel =
              level[static_cast<std::size_t>(row.index) * width + column.index];
          for (int c = 0; c < 4; ++c) sum[c] += row.weight * column.weight * texel[c];
        }
      }
      for (int c = 0; c < 4; ++c) next[y * taps_x.size() + x][c] = static_cast<float>(sum[c]);
    }
  }
  return next;
}

Rgba8 encode_texel(const Linear& texel, bool srgb) {
  return {encode_channel(texel[0], srgb), encode_channel(texel[1], srgb),
          encode_channel(texel[2], srgb), encode_channel(texel[3], false)};
}

// Appends levels 1 .. to texture.texels, which holds level 0. Each level is made from the
// previous one kept in floats, not from its bytes, so rounding does not pile up down the chain.
void make_mip_chain(TextureImage& texture) {
  const int levels = mip_level_count(texture.width, texture.height);
  texture.levels.assign(1, {texture.width, texture.height, 0});
  texture.texels.reserve(
      static_cast<std::size_t>(texture_bytes(texture.width, texture.height) / 4));
  const std::span<const float> decode = texel_decode_table();
  const int colour = texture.srgb ? 0 : 256;
  std::vector<Linear> level(texture.texels.size());
  for (std::size_t i = 0; i < level.size(); ++i) {
    const Rgba8 t = texture.texels[i];
    level[i] = {decode[colour + t.r], decode[colour + t.g], decode[colour + t.b],
                decode[256 + t.a]};
  }
  int width = texture.width, height = texture.height;
  for (int index = 1; index < levels; ++index) {
    level = next_level(level, width, height);
    width = std::max(1, width / 2);
    height = std::max(1, height / 2);
    texture.levels.push_back({width, height, static_cast<long long>(texture.texels.size())});
    for (const Linear& texel : level)
      texture.texels.push_back(encode_texel(texel, texture.srgb));
  }
}

struct StbPixels {
  unsigned char* data = nullptr;
  ~StbPixels() { stbi_image_free(data); }
};

} // namespace

TextureImage make_texture(std::string name, int width, int height, std::vector<Rgba8> level0,
                          bool srgb, const TextureLimits& limits) {
  check_texture_size(name, width, height, limits);
  if (level0.size() != static_cast<std::size_t>(width) * height) {
    throw InputError(name + ": " + std::to_string(level0.size()) + " texels given for a " +
                     std::to_string(width) + " x " + std::to_string(height) + " texture");
  }
  TextureImage texture{std::move(name), width, height, srgb, std::move(level0), {}};
  make_mip_chain(texture);
  return texture;
}

// [listing:load_texture]
TextureImage load_texture(const std::string& path, bool srgb, const TextureLimits& limits) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    throw InputError(path + ": cannot read the texture: no such file");
  }
  if (!std::filesystem::is_regular_file(path, error)) {
    throw InputError(path + ": cannot read the texture: not a file");
  }
  // The header first: a file that claims 100 000 x 100 000 texels is refused before stb_image
  // allocates 40 GB for it.
  int width = 0, height = 0, channels = 0;
  if (stbi_info(path.c_str(), &width, &height, &channels) == 0) {
    throw InputError(path + ": not a PNG or JPEG texture that can be read (" +
                     stbi_failure_reason() + ")");
  }
  check_texture_size(path, width, height, limits);
  StbPixels pixels;
  pixels.data = stbi_load(path.c_str(), &width, &height, &channels, 4); // always RGBA
  if (pixels.data == nullptr) {
    throw InputError(path + ": the texture's pixels cannot be decoded (" +
                     stbi_failure_reason() + ")");
  }
  const auto* first = reinterpret_cast<const Rgba8*>(pixels.data);
  std::vector<Rgba8> level0(first, first + static_cast<std::size_t>(width) * height);
  return make_texture(path, width, height, std::move(level0), srgb, limits);
}
// [/listing:load_texture]

const char* to_string(TextureFilter filter) {
  switch (filter) {
  case TextureFilter::point:
    return "point";
  case TextureFilter::bilinear:
    return "bilinear";
  case TextureFilter::trilinear:
    return "trilinear";
  }
  return "?";
}

TextureFilter parse_texture_filter(const std::string& text) {
  if (text == "point") return TextureFilter::point;
  if (text == "bilinear") return TextureFilter::bilinear;
  if (text == "trilinear") return TextureFilter::trilinear;
  throw UsageError("unknown texture filter '" + text + "' (point, bilinear or trilinear)");
}

TextureView view_of(const TextureImage& image, const Rgba8* texels) {
  TextureView view;
  view.texels = texels;
  view.width = image.width;
  view.height = image.height;
  view.levels = image.level_count();
  for (int level = 0; level < view.levels; ++level) {
    view.offset[level] = static_cast<int>(image.levels[level].offset);
  }
  view.srgb = image.srgb;
  return view;
}

HostTextures::HostTextures(std::span<const TextureImage> images) {
  views_.reserve(images.size());
  for (const TextureImage& image : images)
    views_.push_back(view_of(image, image.texels.data()));
}

TextureTable HostTextures::table(TextureFilter filter) const {
  TextureTable table;
  table.views = views_.data();
  table.decode = texel_decode_table().data();
  table.count = static_cast<int>(views_.size());
  table.filter = filter;
  table.objects_on = false;
  return table;
}

} // namespace rt::ch12
