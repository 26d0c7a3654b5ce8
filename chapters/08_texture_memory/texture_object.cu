// Chapter 08: texture objects, owned. See texture_object.h.
#include "texture_object.h"

#include <atomic>
#include <string>

#include "rt/cuda_check.h"
#include "rt/error.h"
#include "rt/report.h"

namespace rt::ch08 {
namespace {
std::atomic<long long> g_live{0};
} // namespace

std::size_t texture_texel_limit() {
  int device = 0, width = 0;
  RT_CUDA_CHECK(cudaGetDevice(&device));
  RT_CUDA_CHECK(cudaDeviceGetAttribute(&width, cudaDevAttrMaxTexture1DLinearWidth, device));
  return static_cast<std::size_t>(width);
}

void check_texel_count(std::size_t count, std::size_t limit, const char* what) {
  if (count <= limit) return;
  throw Error(std::string("texture path: ") + what + " need " +
              group_digits(static_cast<long long>(count)) +
              " float4 texels, more than this GPU's limit of " +
              group_digits(static_cast<long long>(limit)) +
              " for a 1D texture over linear memory; use --memory global or float4");
}

// [listing:texture_create]
TextureObject::TextureObject(const float4* records, std::size_t count) {
  if (count == 0 || records == nullptr) throw Error("TextureObject: no texels to view");
  check_texel_count(count, texture_texel_limit(), "the records");
  cudaResourceDesc resource{};
  resource.resType = cudaResourceTypeLinear; // plain device memory, no CUDA array
  resource.res.linear.devPtr = const_cast<float4*>(records);
  resource.res.linear.desc = cudaCreateChannelDesc<float4>();
  resource.res.linear.sizeInBytes = count * sizeof(float4);
  cudaTextureDesc texture{};
  texture.readMode = cudaReadModeElementType; // the floats as stored, no conversion
  texture.filterMode = cudaFilterModePoint;   // no interpolation between texels
  texture.normalizedCoords = 0;               // tex1Dfetch takes the texel's index
  RT_CUDA_CHECK(cudaCreateTextureObject(&handle_, &resource, &texture, nullptr));
  ++g_live;
}
// [/listing:texture_create]

TextureObject& TextureObject::operator=(TextureObject&& other) noexcept {
  if (this != &other) {
    reset();
    handle_ = other.handle_;
    other.handle_ = 0;
  }
  return *this;
}

void TextureObject::reset() noexcept {
  if (handle_ == 0) return;
  cudaDestroyTextureObject(handle_); // never throws from a destructor
  handle_ = 0;
  --g_live;
}

long long TextureObject::live() { return g_live.load(); }

} // namespace rt::ch08
