// Chapter 02: frames on either backend, and the CUDA-GL pixel buffer. See frames.h.
#include "frames.h"

#include <cuda_gl_interop.h>

#include "gl_check.h"
#include "rt/backend_image.h"
#include "rt/cuda_check.h"
#include "rt/device_buffer.h"

namespace rt::ch02 {

void render_frame(Backend backend, Rgba8* pixels, Extent extent, int frame) {
  const int width = extent.width, height = extent.height;
  for_each_pixel(backend, extent, [=] RT_HD(int x, int y) {
    pixels[y * width + x] = animated_pattern(x, y, width, height, frame);
  });
}

Image render_frame_image(Backend backend, Extent extent, int frame) {
  return render_into_image(
      backend, extent, [&](Rgba8* pixels) { render_frame(backend, pixels, extent, frame); });
}

Image torn_frame(Extent extent, int frame) {
  const Image before = render_frame_image(Backend::cpu, extent, frame - 1);
  const Image after = render_frame_image(Backend::cpu, extent, frame);
  const BlockShape block{}; // the launch helper's 16x16
  const int blocks_per_row = blocks_to_cover(extent.width, block.x);
  const int warps_per_block = block.x * block.y / 32;
  Image picture(2 * extent.width, extent.height);
  for (int y = 0; y < extent.height; ++y)
    for (int x = 0; x < extent.width; ++x) {
      const int block_index = (y / block.y) * blocks_per_row + x / block.x;
      const int warp_in_block = ((y % block.y) * block.x + x % block.x) / 32;
      const std::uint32_t warp = std::uint32_t(block_index * warps_per_block + warp_in_block);
      const bool written = ((warp * 2654435761u) >> 31) == 0u;
      const Rgba8 shown = written ? after.at(x, y) : before.at(x, y);
      const Rgba8 dim{std::uint8_t(shown.r / 3), std::uint8_t(shown.g / 3),
                      std::uint8_t(shown.b / 3), 255};
      picture.at(x, y) = shown;
      picture.at(extent.width + x, y) =
          shown == after.at(x, y) ? dim : Rgba8{255, 255, 255, 255};
    }
  return picture;
}

GlPixelBuffer::GlPixelBuffer(std::size_t bytes) : bytes_(bytes) {
  RT_GL_CHECK(glGenBuffers(1, &id_));
  RT_GL_CHECK(glBindBuffer(GL_PIXEL_UNPACK_BUFFER, id_));
  // GL_STREAM_DRAW: written once per frame (by CUDA), read once by GL's texture upload.
  RT_GL_CHECK(glBufferData(GL_PIXEL_UNPACK_BUFFER, GLsizeiptr(bytes), nullptr, GL_STREAM_DRAW));
  RT_GL_CHECK(glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0));
}

GlPixelBuffer::~GlPixelBuffer() {
  if (id_ != 0) glDeleteBuffers(1, &id_);
}

// [listing:register_map]
CudaGlRegistration::CudaGlRegistration(const GlPixelBuffer& buffer) {
  // WriteDiscard: CUDA will overwrite the whole buffer, so the driver need not preserve (or
  // copy) its old contents when it hands the buffer over.
  RT_CUDA_CHECK(cudaGraphicsGLRegisterBuffer(&resource_, buffer.id(),
                                             cudaGraphicsRegisterFlagsWriteDiscard));
}

CudaGlRegistration::~CudaGlRegistration() {
  if (resource_ != nullptr) cudaGraphicsUnregisterResource(resource_);
}

CudaGlRegistration::Mapping::Mapping(cudaGraphicsResource_t resource) : resource_(resource) {
  RT_CUDA_CHECK(cudaGraphicsMapResources(1, &resource_));
  std::size_t bytes = 0;
  void* pointer = nullptr;
  const cudaError_t code = cudaGraphicsResourceGetMappedPointer(&pointer, &bytes, resource_);
  if (code != cudaSuccess) cudaGraphicsUnmapResources(1, &resource_); // no half-open state
  RT_CUDA_CHECK(code);
  pixels_ = static_cast<Rgba8*>(pointer);
}

CudaGlRegistration::Mapping::~Mapping() { cudaGraphicsUnmapResources(1, &resource_); }
// [/listing:register_map]

} // namespace rt::ch02
