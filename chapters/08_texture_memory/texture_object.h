// Chapter 08: a CUDA texture object over linear device memory, owned. The texture object is
// the modern, bindless form of the texture references the thesis used (removed in CUDA 12):
// a handle made at run time and passed to kernels like any value.
#pragma once

#include <cstddef>

#include <cuda_runtime_api.h>
#include <vector_types.h>

namespace rt::ch08 {

// [listing:texture_object]
class TextureObject {
public:
  TextureObject() = default;
  // A texture of `count` float4 texels over `records` (device memory, which must outlive the
  // texture). Throws Error naming the limit when count exceeds this GPU's width for a 1D
  // texture over linear memory, or when CUDA refuses.
  TextureObject(const float4* records, std::size_t count);
  ~TextureObject() { reset(); }

  TextureObject(const TextureObject&) = delete;
  TextureObject& operator=(const TextureObject&) = delete;
  TextureObject(TextureObject&& other) noexcept : handle_(other.handle_) { other.handle_ = 0; }
  TextureObject& operator=(TextureObject&& other) noexcept;

  cudaTextureObject_t handle() const { return handle_; }
  // Texture objects created and not yet destroyed, by this class in this process.
  static long long live();

private:
  void reset() noexcept;
  cudaTextureObject_t handle_ = 0; // 0: none
};
// [/listing:texture_object]

// The widest 1D texture over linear memory this GPU allows, in texels.
std::size_t texture_texel_limit();
// Throws Error when `count` texels of `what` exceed `limit`: the one line a reader sees.
void check_texel_count(std::size_t count, std::size_t limit, const char* what);

} // namespace rt::ch08
