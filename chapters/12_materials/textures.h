// Chapter 12: textures. An image a material reads at each hit: decoded once on the host (PNG or
// JPEG through stb_image), its mip chain made in linear space, and sampled the same way by both
// backends. On the GPU the texels can also go through CUDA texture objects, which do here what
// they are made for (chapter 08 used them over plain records): sRGB decode, wrapping, bilinear
// and trilinear filtering in the texture unit.
//
// Coordinates: uv as glTF gives them, u to the right and v DOWN, (0, 0) the top-left corner of
// the image, row 0 of the texels at the top (as rt::Image stores a picture, and as a CUDA array
// is laid out). OBJ's vt has v up; the OBJ loader flips it (v = 1 - vt) before it gets here.
// Texel (x, y) of a w x h level is centred on uv ((x + 0.5) / w, (y + 0.5) / h). Outside [0, 1]
// the image repeats (wrap mode "repeat", glTF's default).
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <cuda_runtime_api.h>

#include "rt/hd.h"
#include "rt/image.h"
#include "rt/vec.h"

namespace rt::ch12 {

// A texel as the kernels use it: linear red, green, blue and alpha.
struct Vec4f {
  float x = 0.0f, y = 0.0f, z = 0.0f, w = 0.0f;
};
RT_HD constexpr Vec4f operator+(Vec4f a, Vec4f b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w};
}
RT_HD constexpr Vec4f operator*(Vec4f a, float s) {
  return {a.x * s, a.y * s, a.z * s, a.w * s};
}

// The most mip levels a texture has: 2^(k_max_levels - 1) = 32768 texels on its long side.
inline constexpr int k_max_levels = 16;

// [listing:texture_limits]
// What a scene's textures may take, all levels of all textures together, checked from the
// files' headers before a texel is decoded. The mip chain adds a third to level 0, so a
// 16384 x 16384 RGBA8 texture takes 16384^2 * 4 * 4/3 = about 1.43 GB: over the default cap of
// 1 GiB, it is refused before anything is allocated; 8192 x 8192 (358 MB) fits three times.
struct TextureLimits {
  int max_side = 16384;            // texels, on either side of level 0
  long long max_bytes = 1LL << 30; // RGBA8 bytes of every level of every texture
};
// [/listing:texture_limits]

// [listing:texture_image]
struct TextureLevel {
  int width = 0, height = 0; // max(1, floor(level 0's / 2^level))
  long long offset = 0;      // where its first texel is in TextureImage::texels
};

struct TextureImage {
  std::string name;          // the file it came from, or what made it
  int width = 0, height = 0; // level 0
  bool srgb = true;          // colour (base colour, emission): the bytes are sRGB-encoded;
                             // data (roughness, metallic): the bytes are linear
  std::vector<Rgba8> texels; // every level, level 0 first, rows top to bottom
  std::vector<TextureLevel> levels;

  int level_count() const { return static_cast<int>(levels.size()); }
};
// [/listing:texture_image]

// floor(log2(max(width, height))) + 1: the levels down to 1 x 1.
int mip_level_count(int width, int height);
// RGBA8 bytes of every level of a width x height texture.
long long texture_bytes(int width, int height);
long long texture_bytes(std::span<const TextureImage> textures);

// Throws InputError "<name>: <width> x <height> texture ..." when a texture of that size
// breaks `limits` (bytes_before: what the scene's other textures already take) or is no image
// at all (a side of 0 or less). Done before decoding or allocating anything.
void check_texture_size(const std::string& name, int width, int height,
                        const TextureLimits& limits, long long bytes_before = 0);
// Throws InputError naming `where` when the textures together break `limits`.
void check_texture_total(std::span<const TextureImage> textures, const TextureLimits& limits,
                         const std::string& where);

// Reads a PNG or JPEG file (8 bits per channel; grey, grey + alpha and RGB get alpha 255) and
// makes its mip chain. Throws InputError, one line naming the file, for a file that is missing,
// unreadable or corrupt, or whose size (read from its header first) breaks `limits`.
TextureImage load_texture(const std::string& path, bool srgb, const TextureLimits& limits = {});
// A texture made in memory: level0 holds width * height texels, rows top to bottom.
TextureImage make_texture(std::string name, int width, int height, std::vector<Rgba8> level0,
                          bool srgb, const TextureLimits& limits = {});

// The sRGB transfer functions (IEC 61966-2-1), on values in [0, 1].
double srgb_to_linear(double encoded);
double linear_to_srgb(double linear);
// Nearest byte of a linear value in [0, 1], sRGB-encoded or not.
std::uint8_t encode_channel(double linear, bool srgb);

// The 512 floats every texel is decoded through, on both backends: entry c is byte c
// sRGB-decoded, entry 256 + c is c / 255 (linear data, and alpha). One table, computed once in
// double and rounded, so the CPU and the GPU's software path decode a byte to the same float;
// a maths library's powf differs by an ulp between the two.
inline constexpr int k_decode_table_size = 512;
std::span<const float> texel_decode_table();

// [listing:texture_view]
enum class TextureFilter : int {
  point,     // the nearest texel of level 0
  bilinear,  // the four nearest texels of level 0, weighted
  trilinear, // bilinear in the two levels around the ray cone's LOD, blended
};

// One texture as the kernels see it: a view of TextureImage's texels, in host or device memory.
struct TextureView {
  const Rgba8* texels = nullptr;
  int width = 0, height = 0, levels = 0;
  int offset[k_max_levels] = {}; // first texel of each level
  bool srgb = true;
};

// The view of `image` whose texels are at `texels`: its own, or a copy in device memory.
TextureView view_of(const TextureImage& image, const Rgba8* texels);

// A scene's textures for one backend and one filter.
struct TextureTable {
  const TextureView* views = nullptr;           // count of them
  const cudaTextureObject_t* objects = nullptr; // device memory, count of them, or none
  const float* decode = nullptr;                // texel_decode_table(), on the same backend
  int count = 0;
  TextureFilter filter = TextureFilter::bilinear;
  // On the GPU: true reads through the texture objects (the texture unit filters), false runs
  // the software filter below with plain loads, as the CPU does (chapter 08's comparison).
  bool objects_on = false;
};
// [/listing:texture_view]

// How far the texture unit's filtering may be from the software filter, on texels in [0, 1].
// The hardware computes its bilinear weights (and the blend between two mip levels) with 8
// fractional bits: each of the three weights may be off by up to 1/256 of the difference it
// weighs, at most 1. Its sRGB decode is not documented to the bit: 1e-3 more. Point sampling
// has no weights and is exact: the point objects read the bytes and decode them through
// texel_decode_table() as the software path does.
inline constexpr float k_hardware_filter_tolerance = 3.0f / 256.0f + 1e-3f;

RT_HD inline int level_width(const TextureView& view, int level) {
  return max_of(1, view.width >> level);
}
RT_HD inline int level_height(const TextureView& view, int level) {
  return max_of(1, view.height >> level);
}

// u - floor(u), in [0, 1] (1 only where rounding gives it, for a tiny negative u); a coordinate
// that is NaN or infinite reads from 0 rather than from an index that is not one.
RT_HD inline float wrap_unit(float u) {
  const float wrapped = u - floorf(u);
  return wrapped >= 0.0f && wrapped <= 1.0f ? wrapped : 0.0f;
}

RT_HD inline Vec4f decode_texel(Rgba8 texel, bool srgb, const float* decode) {
  const int colour = srgb ? 0 : 256;
  return {decode[colour + texel.r], decode[colour + texel.g], decode[colour + texel.b],
          decode[256 + texel.a]};
}

RT_HD inline Rgba8 texel_at(const TextureView& view, int level, int x, int y) {
  return view.texels[view.offset[level] + y * level_width(view, level) + x];
}

// The texel whose square holds uv, in level 0.
RT_HD inline Vec4f sample_point(const TextureView& view, const float* decode, Vec2f uv) {
  int x = static_cast<int>(floorf(wrap_unit(uv.x) * static_cast<float>(view.width)));
  int y = static_cast<int>(floorf(wrap_unit(uv.y) * static_cast<float>(view.height)));
  x = x >= view.width ? x - view.width : x; // u rounded to exactly 1 is u = 0
  y = y >= view.height ? y - view.height : y;
  return decode_texel(texel_at(view, 0, x, y), view.srgb, decode);
}

// [listing:sample_bilinear]
// The four texels around uv in one level, each decoded to linear first (filtering sRGB bytes
// would darken every edge between light and dark), weighted by how close uv is to each centre.
RT_HD inline Vec4f sample_bilinear(const TextureView& view, const float* decode, int level,
                                   Vec2f uv) {
  const int width = level_width(view, level), height = level_height(view, level);
  const float x = wrap_unit(uv.x) * static_cast<float>(width) - 0.5f; // in texel centres
  const float y = wrap_unit(uv.y) * static_cast<float>(height) - 0.5f;
  const float x_floor = floorf(x), y_floor = floorf(y);
  const float tx = x - x_floor, ty = y - y_floor;
  int x0 = static_cast<int>(x_floor), y0 = static_cast<int>(y_floor); // -1 .. side - 1
  x0 = x0 < 0 ? width - 1 : x0;
  y0 = y0 < 0 ? height - 1 : y0;
  const int x1 = x0 + 1 == width ? 0 : x0 + 1, y1 = y0 + 1 == height ? 0 : y0 + 1;
  const Vec4f top =
      decode_texel(texel_at(view, level, x0, y0), view.srgb, decode) * (1.0f - tx) +
      decode_texel(texel_at(view, level, x1, y0), view.srgb, decode) * tx;
  const Vec4f bottom =
      decode_texel(texel_at(view, level, x0, y1), view.srgb, decode) * (1.0f - tx) +
      decode_texel(texel_at(view, level, x1, y1), view.srgb, decode) * tx;
  return top * (1.0f - ty) + bottom * ty;
}
// [/listing:sample_bilinear]

// Bilinear in the levels floor(lod) and floor(lod) + 1, blended by lod's fraction; lod is
// clamped to [0, levels - 1] (NaN reads level 0).
RT_HD inline Vec4f sample_trilinear(const TextureView& view, const float* decode, Vec2f uv,
                                    float lod) {
  const float last = static_cast<float>(view.levels - 1);
  lod = lod >= 0.0f ? (lod <= last ? lod : last) : 0.0f;
  const float lower = floorf(lod);
  const float blend = lod - lower;
  const int level = static_cast<int>(lower);
  const Vec4f near_level = sample_bilinear(view, decode, level, uv);
  if (blend == 0.0f) return near_level;
  return near_level * (1.0f - blend) + sample_bilinear(view, decode, level + 1, uv) * blend;
}

// [listing:sample_texture]
// Texture `index` at uv, linear RGBA. lod (the ray cone's, ray_cone.h) is read by the
// trilinear filter only. An index outside the table (k_no_texture) reads white, which leaves
// the factor it multiplies as it is.
RT_HD inline Vec4f sample_texture(const TextureTable& table, int index, Vec2f uv, float lod) {
  if (index < 0 || index >= table.count) return {1.0f, 1.0f, 1.0f, 1.0f};
#if defined(__CUDA_ARCH__)
  if (table.objects_on) {
    const cudaTextureObject_t object = table.objects[index];
    const float u = wrap_unit(uv.x), v = wrap_unit(uv.y);
    if (table.filter == TextureFilter::point) {
      const uchar4 bytes = tex2D<uchar4>(object, u, v); // the bytes, decoded as the CPU does
      return decode_texel({bytes.x, bytes.y, bytes.z, bytes.w}, table.views[index].srgb,
                          table.decode);
    }
    if (table.filter == TextureFilter::bilinear) {
      const float4 texel = tex2D<float4>(object, u, v);
      return {texel.x, texel.y, texel.z, texel.w};
    }
    const float4 texel = tex2DLod<float4>(object, u, v, lod >= 0.0f ? lod : 0.0f);
    return {texel.x, texel.y, texel.z, texel.w};
  }
#endif
  const TextureView& view = table.views[index];
  switch (table.filter) {
  case TextureFilter::point:
    return sample_point(view, table.decode, uv);
  case TextureFilter::bilinear:
    return sample_bilinear(view, table.decode, 0, uv);
  case TextureFilter::trilinear:
    break;
  }
  return sample_trilinear(view, table.decode, uv, lod);
}
// [/listing:sample_texture]

const char* to_string(TextureFilter filter);
// "point", "bilinear" or "trilinear"; anything else is a UsageError.
TextureFilter parse_texture_filter(const std::string& text);

// The textures for the CPU backend: views of the images' texels, which must outlive it.
class HostTextures {
public:
  HostTextures() = default;
  explicit HostTextures(std::span<const TextureImage> images);
  TextureTable table(TextureFilter filter) const;

private:
  std::vector<TextureView> views_;
};

// The textures on the GPU, owned: each image's levels in a CUDA mipmapped array with a texture
// object for each filter over it, and a plain copy of the texels with their views for the
// software path. Nothing leaks when a constructor throws midway (CUDA errors as rt::CudaError).
class DeviceTextures {
public:
  DeviceTextures() = default;
  explicit DeviceTextures(std::span<const TextureImage> images);
  ~DeviceTextures();
  DeviceTextures(const DeviceTextures&) = delete;
  DeviceTextures& operator=(const DeviceTextures&) = delete;
  DeviceTextures(DeviceTextures&& other) noexcept;
  DeviceTextures& operator=(DeviceTextures&& other) noexcept;

  // The table a kernel reads: device pointers throughout.
  TextureTable table(TextureFilter filter, bool objects_on) const;
  int count() const { return count_; }
  // CUDA arrays and texture objects made by this class and not yet destroyed, in this process.
  static long long live_arrays();
  static long long live_objects();

private:
  void release() noexcept;

  int count_ = 0;
  std::vector<cudaMipmappedArray_t> arrays_;    // one per image
  std::vector<cudaTextureObject_t> objects_[3]; // per filter, one per image
  cudaTextureObject_t* d_objects_[3] = {};      // the same, on the device
  Rgba8* d_texels_ = nullptr;                   // every image's levels, end to end
  TextureView* d_views_ = nullptr;              // views into d_texels_
  float* d_decode_ = nullptr;                   // texel_decode_table()
};

// Samples on the GPU, one thread a query, through `table` (DeviceTextures::table): the results
// the CPU's sample_texture is compared with.
struct TextureQuery {
  int index = 0;
  Vec2f uv{};
  float lod = 0.0f;
};
std::vector<Vec4f> sample_textures_on_gpu(const TextureTable& table,
                                          std::span<const TextureQuery> queries);

} // namespace rt::ch12
